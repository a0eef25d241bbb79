#version 460
// Adds sigma * (length of the pixel ray inside the tetrahedron) to the optical-depth target.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };

#include "interval_ray.glsl"

layout(location = 0) in vec2 v_inv_depth;
layout(location = 2) in vec4 v_relative;
layout(location = 1) perprimitiveEXT flat in vec4 p_reference;
layout(location = 0) out float out_optical_depth;

void main() {
  IntervalRay r = interval_ray(v_inv_depth, v_relative, p_reference);
  if (!end_at(r, pixel_depth_limit())) {
    out_optical_depth = 0.0;
    return;
  }
  // sigma is linear along the segment, so its integral is the length times its mean, the
  // mean of its values at the two ends.
  float mean_sigma = 0.5 * (r.field_front + r.field_back);
  out_optical_depth = max(mean_sigma, 0.0) * interval_length(r);
}
