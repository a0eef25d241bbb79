// Shadows for the shared shading code, traced from ray-generation shaders: defines
// PRISMOID_SURFACE_SHADOWS, includes shading.glsl (which then only declares the visibility
// hooks) and defines the hooks with shadow rays through the scene's TLAS. The pipeline must
// list surface/rt/shadow.rmiss as miss shader PRISMOID_SURFACE_MISS_SHADOW and bind the TLAS at
// PRISMOID_SURFACE_BINDING_TLAS (surface::scene_bindings with tlas = true).
#ifndef PRISMOID_SURFACE_SHADOW_RAYS_GLSL
#define PRISMOID_SURFACE_SHADOW_RAYS_GLSL

#extension GL_EXT_ray_tracing : require

#define PRISMOID_SURFACE_SHADOWS
#include "shading.glsl"

layout(set = 0, binding = PRISMOID_SURFACE_BINDING_TLAS) uniform accelerationStructureEXT scene_tlas;
layout(location = PRISMOID_SURFACE_PAYLOAD_SHADOW) rayPayloadEXT uint shadow_visible;

// A ray origin moved off the surface along its viewer-side geometric normal by a few float
// ulps of the position's magnitude, so the surface it starts on is not found again (the
// rounding of a float position, not a scene-dependent epsilon, sets the distance).
vec3 offset_ray_origin(vec3 p, vec3 n) {
  float scale = max(max(abs(p.x), abs(p.y)), max(abs(p.z), 1.0));
  return p + n * (scale * 1.0e-5);
}

// 1 when nothing lies on origin + t direction for t in (t_min, t_max).
float trace_shadow(vec3 origin, vec3 direction, float t_min, float t_max) {
  if (!(t_max > t_min)) return 1.0;
  shadow_visible = 0u;
  traceRayEXT(scene_tlas, gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsSkipClosestHitShaderEXT,
              0xFF, 0, 0, PRISMOID_SURFACE_MISS_SHADOW, origin, t_min, direction, t_max, PRISMOID_SURFACE_PAYLOAD_SHADOW);
  return float(shadow_visible);
}

float point_light_visibility(SurfacePoint sp, uint light, vec3 to_light) {
  vec3 origin = offset_ray_origin(sp.position, sp.geometric);
  vec3 to = point_lights[light].position.xyz - origin;
  float d = length(to);
  return trace_shadow(origin, to / d, 0.0, d * (1.0 - 1.0e-5));
}

float directional_light_visibility(SurfacePoint sp, uint light, vec3 to_light) {
  return trace_shadow(offset_ray_origin(sp.position, sp.geometric), to_light, 0.0, uintBitsToFloat(0x7f7fffffu));
}

// The emitter's shadow sample points, as barycentric weights of its corners: the centroids of
// the four triangles of its midpoint subdivision (renderer/reference evaluates the same points).
#define PRISMOID_EMITTER_SHADOW_SAMPLES 4u
vec3 emitter_shadow_sample(uint k) {
  if (k == 3u) return vec3(1.0 / 3.0);
  vec3 b = vec3(1.0 / 6.0);
  b[k] = 2.0 / 3.0;
  return b;
}

// The visible fraction of an emissive triangle: PRISMOID_EMITTER_SHADOW_SAMPLES fixed points on
// it, each weighted by its unshadowed contribution (Heitz, Hill & McGuire 2018's ratio).
float emitter_visibility(SurfacePoint sp, uint emitter) {
  EmitterGpu e = emitters[emitter];
  vec3 origin = offset_ray_origin(sp.position, sp.geometric);
  float seen = 0.0, total = 0.0;
  for (uint k = 0u; k < PRISMOID_EMITTER_SHADOW_SAMPLES; ++k) {
    vec3 b = emitter_shadow_sample(k);
    vec3 q = b.x * e.v0.xyz + b.y * e.v1.xyz + b.z * e.v2.xyz;
    vec3 to = q - origin;
    float d2 = dot(to, to);
    if (!(d2 > 0.0)) continue;
    float d = sqrt(d2);
    vec3 w = to / d;
    float weight = max(dot(w, sp.normal), 0.0) * max(-dot(w, e.normal.xyz), 0.0) / d2;
    if (!(weight > 0.0)) continue;
    total += weight;
    seen += weight * trace_shadow(origin, w, 0.0, d * (1.0 - 1.0e-4));
  }
  return total > 0.0 ? seen / total : 1.0;
}

#endif
