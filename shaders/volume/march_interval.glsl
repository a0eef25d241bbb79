// Marching inside one interval (Tricard 2024, section 3.2), as every interval backend marches:
// a field that is not linear in the cell is sampled along the interval in n equal steps of at
// most the step setting (midpoint rule over the exact interval, so a linear field integrates
// exactly). The caller declares `frame` and `tf_samples` and includes analytic_field.glsl.
#ifndef PRISMOID_MARCH_INTERVAL_GLSL
#define PRISMOID_MARCH_INTERVAL_GLSL

#include "march_ray.glsl"
#include "transfer_lookup.glsl"

// Optical depth: the integral of sigma = density_scale * max(field, 0), each sample's
// extinction held to the cap (float_limits.hpp); the cap leaves room for the sum.
float march_optical_depth(IntervalRay r, vec4 reference) {
  float len = interval_length(r);
  MarchRay m = march_ray(r, reference);
  uint n = march_steps(len);
  float depth_step = (r.rel_back - r.rel_front) / float(n), h = len / float(n);
  float sum = 0.0;
  for (uint i = 0u; i < n; ++i)
    sum += min(frame.march.z * max(field_at(field_point(m, r.rel_front + (float(i) + 0.5) * depth_step)), 0.0), frame.march.w);
  return sum * h;
}

// Colour: each step has the colour and extinction of its midpoint; a step of constant sigma
// and colour c contributes c (1 - e^(-sigma h)) with alpha 1 - e^(-sigma h), composited front
// to back within the interval (premultiplied colour, alpha).
vec4 march_color(IntervalRay r, vec4 reference) {
  float len = interval_length(r);
  MarchRay m = march_ray(r, reference);
  uint n = march_steps(len);
  float depth_step = (r.rel_back - r.rel_front) / float(n), h = len / float(n);
  vec4 total = vec4(0.0);
  for (uint i = 0u; i < n && total.a < 1.0; ++i) {
    float x = field_at(field_point(m, r.rel_front + (float(i) + 0.5) * depth_step)) * frame.transfer.x + frame.transfer.y;
    vec4 s = tf_at(x);
    float alpha = 1.0 - exp(-s.w * h);
    total += (1.0 - total.a) * vec4(s.rgb * alpha, alpha);
  }
  return total;
}

#endif
