#version 460
// Emission-absorption of one cell's segment along the pixel ray (beyond the paper): the
// normalized scalar at the front and back of the interval comes from the cell's linear field;
// the segment's premultiplied colour and opacity come either from exact integration piece by
// piece of the transfer function, or from the pre-integrated table (a quality setting). The
// blend state composites front to back ("under"): dst += (1 - dst.a) * src.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };
layout(std430, set = 0, binding = PRISMOID_BINDING_PREINTEGRATED) readonly buffer Table { vec4 texels[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TRANSFER) readonly buffer Transfer { vec4 tf_samples[]; };

layout(location = 0) in vec2 v_inv_depth;
layout(location = 2) in vec4 v_relative;
layout(location = 1) perprimitiveEXT flat in vec4 p_reference;  // w: the normalized scalar at the cell's reference point
layout(location = 0) out vec4 out_color;

#include "interval_ray.glsl"
#include "segment_emission.glsl"

void main() {
  IntervalRay r = interval_ray(v_inv_depth, v_relative, p_reference);
  if (!end_at(r, pixel_depth_limit())) {
    out_color = vec4(0.0);
    return;
  }
  float len = interval_length(r);
  // A non-finite interval (cannot happen for proxies that pass the area test) adds nothing.
  if (!(len > 0.0) || isinf(len)) {
    out_color = vec4(0.0);
    return;
  }
  out_color = segment_emission(r.field_front, r.field_back, len);
}
