#version 460
// Marching inside intervals (Tricard 2024, section 3.2; march_interval.glsl): optical depth
// adds sigma = density_scale * max(field, 0) (additive blend, any order); colour composites
// the transfer function of the field front to back within the interval, and the blend
// composites the cells in the order they are drawn.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TRANSFER) readonly buffer Transfer { vec4 tf_samples[]; };

#include "analytic_field.glsl"
#include "march_interval.glsl"

layout(location = 0) in vec2 v_inv_depth;
layout(location = 2) in vec4 v_relative;
layout(location = 1) perprimitiveEXT flat in vec4 p_reference;
layout(location = 0) out vec4 out_value;  // optical depth in .x, or premultiplied colour and alpha

void main() {
  IntervalRay r = interval_ray(v_inv_depth, v_relative, p_reference);
  float len = interval_length(r);
  // A non-finite interval (cannot happen for proxies that pass the area test) adds nothing.
  if (!(len > 0.0) || isinf(len)) {
    out_value = vec4(0.0);
    return;
  }
  out_value = frame.field.z == PRISMOID_MARCH_OPTICAL_DEPTH ? vec4(march_optical_depth(r, p_reference), 0.0, 0.0, 0.0)
                                                            : march_color(r, p_reference);
}
