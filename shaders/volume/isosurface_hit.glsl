// The isosurface in one interval, as every interval backend finds it: the first point of the
// interval where the field reaches the isovalue, found by marching in equal steps of at most
// the step setting and bisecting inside the step where it is first reached. An interval that
// starts at or above the isovalue hits at its front (the surface entered in a nearer cell, or
// the camera or the mesh boundary cuts the inside). Shading: a headlight Lambert term on the
// analytic gradient. The caller declares `frame` and includes analytic_field.glsl.
#ifndef PRISMOID_ISOSURFACE_HIT_GLSL
#define PRISMOID_ISOSURFACE_HIT_GLSL

#include "march_ray.glsl"

// Whether the interval holds a hit; if so its shade and its depth along the viewing axis.
bool isosurface_hit(IntervalRay r, vec4 reference, out float shade, out float hit_depth) {
  shade = 0.0;
  hit_depth = 0.0;
  float len = interval_length(r);
  if (!(len >= 0.0) || isinf(len)) return false;
  MarchRay m = march_ray(r, reference);
  float iso = frame.march.y;
  // Marching and bisection run in depth relative to the cell's reference point (march_ray.glsl).
  float hit = r.rel_front;
  if (field_at(field_point(m, r.rel_front)) < iso) {
    uint n = march_steps(len);
    float depth_step = (r.rel_back - r.rel_front) / float(n);
    float lo = r.rel_front, hi = r.rel_front;
    bool found = false;
    for (uint i = 1u; i <= n && !found; ++i) {
      lo = hi;
      hi = i == n ? r.rel_back : r.rel_front + float(i) * depth_step;
      found = field_at(field_point(m, hi)) >= iso;
    }
    if (!found) return false;
    // Bisection until the bracket is one float apart (at most 32 halvings of the step).
    for (int k = 0; k < 32; ++k) {
      float mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      if (field_at(field_point(m, mid)) >= iso) hi = mid;
      else lo = mid;
    }
    hit = hi;
  }
  vec3 p = field_point(m, hit);
  vec3 g = analytic_gradient(frame.field.x, frame.field.y, frame.field_params, p);
  float g_len = length(g);
  float lambert = g_len > 0.0 ? abs(dot(g / g_len, normalize(m.field_per_depth))) : 1.0;
  shade = PRISMOID_ISOSURFACE_AMBIENT + (1.0 - PRISMOID_ISOSURFACE_AMBIENT) * lambert;
  hit_depth = r.front + (hit - r.rel_front);  // absolute, for the distance and the depth test
  return true;
}

#endif
