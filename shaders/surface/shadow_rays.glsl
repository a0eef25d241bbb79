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

// The distance shadow rays keep from the surfaces at their ends (PRISMOID_SHADOW_RAY_OFFSET
// times the scene's scale; shaders/shared/surface.h says why): the scale is the largest
// |vertex coordinate| relative to the origin, so the rounding of float positions, not a unit of
// length, sets it. Without a scale in the frame (frame.subpixel.z = 0) max(|p|, 1) stands in.
float shadow_ray_offset(vec3 p) {
  float m = max(max(abs(p.x), abs(p.y)), abs(p.z));
  float scale = frame.subpixel.z > 0.0 ? max(m, frame.subpixel.z) : max(m, 1.0);
  return scale * PRISMOID_SHADOW_RAY_OFFSET;
}

// A ray origin moved off the surface along its viewer-side geometric normal n by
// shadow_ray_offset(p), so the surface it starts on is not found again.
vec3 offset_ray_origin(vec3 p, vec3 n) { return p + n * shadow_ray_offset(p); }

// 1 when nothing lies on origin + t direction for t in (t_min, t_max).
float trace_shadow(vec3 origin, vec3 direction, float t_min, float t_max) {
  if (!(t_max > t_min)) return 1.0;
  shadow_visible = 0u;
  traceRayEXT(scene_tlas, gl_RayFlagsOpaqueEXT | gl_RayFlagsTerminateOnFirstHitEXT | gl_RayFlagsSkipClosestHitShaderEXT,
              0xFF, 0, 0, PRISMOID_SURFACE_MISS_SHADOW, origin, t_min, direction, t_max, PRISMOID_SURFACE_PAYLOAD_SHADOW);
  return float(shadow_visible);
}

// One segment from the offset origin to the light, ending the offset short of it.
float point_light_visibility(SurfacePoint sp, uint light, vec3 to_light) {
  float offset = shadow_ray_offset(sp.position);
  vec3 origin = sp.position + sp.geometric * offset;
  vec3 to = point_lights[light].position.xyz - origin;
  float d = length(to);
  if (!(d > offset)) return 1.0;
  return trace_shadow(origin, to / d, 0.0, d - offset);
}

float directional_light_visibility(SurfacePoint sp, uint light, vec3 to_light) {
  return trace_shadow(offset_ray_origin(sp.position, sp.geometric), to_light, 0.0, uintBitsToFloat(0x7f7fffffu));
}

// The emitter's shadow sample points, as barycentric weights of its corners: the centroids of
// the four triangles of its midpoint subdivision (the table in shaders/shared/surface.h, which
// renderer/reference reads too).
vec3 emitter_shadow_sample(uint k) {
  const vec3 samples[PRISMOID_EMITTER_SHADOW_SAMPLES] =
      vec3[](vec3(PRISMOID_EMITTER_SHADOW_SAMPLE_0), vec3(PRISMOID_EMITTER_SHADOW_SAMPLE_1),
             vec3(PRISMOID_EMITTER_SHADOW_SAMPLE_2), vec3(PRISMOID_EMITTER_SHADOW_SAMPLE_3));
  return samples[k];
}

// The visible fraction of an emissive triangle: PRISMOID_EMITTER_SHADOW_SAMPLES fixed points on
// it, each weighted by its unshadowed contribution (Heitz, Hill & McGuire 2018's ratio), each
// seen along the segment from the offset origin to the point moved off the emitter towards its
// front (the emitter's own triangle and its coplanar neighbours are then never hit).
//
// The weights are kept in an array and both sums are taken from it after all rays are traced, so
// that the very same weights reach `seen` and `total` and the ratio cannot exceed 1. A weight
// summed into `seen` after a trace, from a value computed before it, need not be the one summed
// into `total`: a compiler may recompute it across traceRayEXT, and next to an emitter's corner
// the weights are sensitive to the last ulp (tests/surface/test_forward.cpp,
// FurnaceNextToACornerStaysAtTheClosedForm; docs/results.md, "The GI furnace's excess").
float emitter_visibility(SurfacePoint sp, uint emitter) {
  EmitterGpu e = emitters[emitter];
  float offset = shadow_ray_offset(sp.position);
  vec3 origin = sp.position + sp.geometric * offset;
  float weights[PRISMOID_EMITTER_SHADOW_SAMPLES];
  float visible[PRISMOID_EMITTER_SHADOW_SAMPLES];
  for (uint k = 0u; k < PRISMOID_EMITTER_SHADOW_SAMPLES; ++k) {
    weights[k] = 0.0;
    visible[k] = 0.0;
    vec3 b = emitter_shadow_sample(k);
    vec3 q = b.x * e.v0.xyz + b.y * e.v1.xyz + b.z * e.v2.xyz;
    vec3 to = q - sp.position;
    float d2 = dot(to, to);
    if (!(d2 > 0.0)) continue;
    vec3 w = to * inversesqrt(d2);
    // Below the geometric horizon the closed-form term has no light (clipped), so no weight.
    float weight = dot(w, sp.geometric) > 0.0 ? max(dot(w, sp.normal), 0.0) * max(-dot(w, e.normal.xyz), 0.0) / d2 : 0.0;
    if (!(weight > 0.0)) continue;
    weights[k] = weight;
    vec3 end = q + e.normal.xyz * shadow_ray_offset(q);
    vec3 segment = end - origin;
    float length_ = length(segment);
    visible[k] = length_ > 0.0 ? trace_shadow(origin, segment / length_, 0.0, length_) : 1.0;
  }
  float seen = 0.0, total = 0.0;
  for (uint k = 0u; k < PRISMOID_EMITTER_SHADOW_SAMPLES; ++k) {
    total += weights[k];
    seen += weights[k] * visible[k];
  }
  return total > 0.0 ? seen / total : 1.0;
}

#endif
