// The fragment's interval on its pixel ray (between the two bounding surfaces its proxy
// interpolates) and where its points lie in the field's coordinates: mesh-local plus
// frame.field_origin, which is 0 for fields whose parameters can be moved into the mesh
// frame; all terms then stay of the size of the mesh and the eye's distance to it, however
// far from the world origin both are. The caller declares `frame`.
#ifndef PRISMOID_INTERVAL_RAY_GLSL
#define PRISMOID_INTERVAL_RAY_GLSL

struct IntervalRay {
  float front, back;      // depths along the viewing axis, front <= back
  float length_per_depth; // world length of one unit of depth along this ray
  vec3 field_eye;         // the field's coordinates at depth 0 (the eye)
  vec3 field_per_depth;   // displacement per unit of depth (world lengths)
};

IntervalRay interval_ray(vec2 inv_depth) {
  IntervalRay r;
  float depth_a = 1.0 / inv_depth.x, depth_b = 1.0 / inv_depth.y;
  r.front = min(depth_a, depth_b);
  r.back = max(depth_a, depth_b);
  vec2 ndc = gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0;
  vec3 ray = vec3(ndc * frame.ray_scale.xy, -1.0);  // the camera-space point at depth d is d * ray
  r.length_per_depth = length(ray);
  r.field_eye = frame.field_origin.xyz + frame.camera_to_mesh[3].xyz;
  r.field_per_depth = mat3(frame.camera_to_mesh) * ray;
  return r;
}

vec3 field_point(IntervalRay r, float depth) { return r.field_eye + r.field_per_depth * depth; }

float field_at(vec3 p) { return analytic_field(frame.field.x, frame.field.y, frame.field_params, p); }

// Equal steps of at most frame.march.x (world length) over `len`; never more than
// PRISMOID_MARCH_MAX_STEPS (the renderer refuses steps that would need more in any cell).
uint march_steps(float len) {
  return uint(clamp(ceil(len / frame.march.x), 1.0, float(PRISMOID_MARCH_MAX_STEPS)));
}

#endif
