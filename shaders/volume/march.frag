#version 460
// Marching inside intervals (Tricard 2024, section 3.2): a field that is not linear in the
// cell is sampled along the fragment's interval in n equal steps of at most the step setting
// (midpoint rule over the exact interval, so a linear field integrates exactly). Optical
// depth adds sigma = density_scale * max(field, 0) (additive blend, any order); colour
// composites the transfer function of the field front to back within the interval, and the
// blend composites the cells in the order they are drawn.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TRANSFER) readonly buffer Transfer { vec4 tf_samples[]; };

#include "analytic_field.glsl"
#include "march_ray.glsl"
#include "transfer_lookup.glsl"

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
  MarchRay m = march_ray(r, p_reference);
  uint n = march_steps(len);
  float depth_step = (r.rel_back - r.rel_front) / float(n), h = len / float(n);
  if (frame.field.z == PRISMOID_MARCH_OPTICAL_DEPTH) {
    float sum = 0.0;
    // Each sample's extinction held to the cap (float_limits.hpp); the cap leaves room for the sum.
    for (uint i = 0u; i < n; ++i)
      sum += min(frame.march.z * max(field_at(field_point(m, r.rel_front + (float(i) + 0.5) * depth_step)), 0.0), frame.march.w);
    out_value = vec4(sum * h, 0.0, 0.0, 0.0);
    return;
  }
  // Colour: each step has the colour and extinction of its midpoint; a step of constant
  // sigma and colour c contributes c (1 - e^(-sigma h)) with alpha 1 - e^(-sigma h).
  vec4 total = vec4(0.0);
  for (uint i = 0u; i < n && total.a < 1.0; ++i) {
    float x = field_at(field_point(m, r.rel_front + (float(i) + 0.5) * depth_step)) * frame.transfer.x + frame.transfer.y;
    vec4 s = tf_at(x);
    float alpha = 1.0 - exp(-s.w * h);
    total += (1.0 - total.a) * vec4(s.rgb * alpha, alpha);
  }
  out_value = total;
}
