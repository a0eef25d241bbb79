#version 460
// Isosurface by marching inside intervals: the first point of the fragment's interval where
// the field reaches the isovalue, found by marching in equal steps of at most the step
// setting and bisecting inside the step where it is first reached. A fragment whose interval
// starts at or above the isovalue hits at its front (the surface entered in a nearer cell,
// or the camera or the mesh boundary cuts the inside). Cells are drawn in any order: the
// depth test (greater, on near / depth) keeps the nearest hit per pixel. Shading: a headlight
// Lambert term on the analytic gradient.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };

#include "analytic_field.glsl"
#include "march_ray.glsl"

layout(location = 0) in vec2 v_inv_depth;
layout(location = 2) in vec4 v_relative;
layout(location = 1) perprimitiveEXT flat in vec4 p_reference;
layout(location = 0) out vec4 out_hit;  // shaded rgb, distance from the eye to the hit (world)

void main() {
  IntervalRay r = interval_ray(v_inv_depth, v_relative, p_reference);
  float len = interval_length(r);
  if (!(len >= 0.0) || isinf(len)) discard;
  MarchRay m = march_ray(r, p_reference);
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
    if (!found) discard;
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
  float shade = PRISMOID_ISOSURFACE_AMBIENT + (1.0 - PRISMOID_ISOSURFACE_AMBIENT) * lambert;
  float hit_depth = r.front + (hit - r.rel_front);  // absolute, for the distance and the depth test
  out_hit = vec4(vec3(shade), hit_depth * r.length_per_depth);
  gl_FragDepth = frame.ray_scale.z / hit_depth;  // near / depth: 1 at the near plane, smaller behind
}
