// Where the points of a fragment's interval (interval_ray.glsl) lie in the field's coordinates,
// for marching: the point at depth (depth_c + rel) on the pixel ray is c + (lateral, 0) + rel *
// ray in camera orientation, with lateral = depth_c * ray.xy - c.xy the pixel ray's offset from
// c at c's depth. Both terms are of the size of the cell and of that offset (sub-pixel errors),
// where depth * ray itself is only exact to the eye's distance. The caller declares `frame`
// and includes analytic_field.glsl.
#ifndef PRISMOID_MARCH_RAY_GLSL
#define PRISMOID_MARCH_RAY_GLSL

#include "interval_ray.glsl"

struct MarchRay {
  vec3 field_base;       // the field's coordinates of the ray's point at c's depth
  vec3 field_per_depth;  // displacement per unit of depth (in the field's coordinates)
};

MarchRay march_ray(IntervalRay r, vec4 reference) {
  MarchRay m;
  vec3 cam_c = (frame.view * vec4(reference.xyz, 1.0)).xyz;
  vec2 lateral = -cam_c.z * r.ray.xy - cam_c.xy;
  mat3 to_mesh = mat3(frame.camera_to_mesh);
  m.field_base = frame.field_origin.xyz + frame.field_origin.w * (reference.xyz + to_mesh * vec3(lateral, 0.0));
  m.field_per_depth = frame.field_origin.w * (to_mesh * r.ray);
  return m;
}

// The field's coordinates of the ray's point at relative depth `rel` (depth minus c's).
vec3 field_point(MarchRay m, float rel) { return m.field_base + m.field_per_depth * rel; }

float field_at(vec3 p) { return analytic_field(frame.field.x, frame.field.y, frame.field_params, p); }

// Equal steps of at most frame.march.x (world length) over `len`; never more than
// PRISMOID_MARCH_MAX_STEPS (the renderer refuses steps that would need more in any cell).
uint march_steps(float len) {
  return uint(clamp(ceil(len / frame.march.x), 1.0, float(PRISMOID_MARCH_MAX_STEPS)));
}

#endif
