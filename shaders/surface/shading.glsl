// Shading of one surface point from every light of the scene: the one piece of shading code
// all surface backends run (forward per pixel; Htex, meshlet atlas and texel shading per
// shading sample), so that backends are compared on equal shading. Its CPU double-precision
// twin is renderer/reference/direct_light.cpp; the conventions are those of
// scene/surface_scene.hpp and the path tracer.
//
// Radiance = emission (front side) + point and directional lights + emissive triangles
// (diffuse lobe in closed form, GGX lobe by the fixed sub-triangle rule) + the sky as ambient
// light for the diffuse lobe (albedo times the sky's cosine-weighted mean over the shading
// normal's hemisphere, in closed form for the gradient sky, ignoring occlusion; the sky's
// reflection in the GGX lobe is left out), each light weighted by its visibility (the shadow
// hook below: 1 without ray tracing, shadow_rays.glsl with it).
#ifndef PRISMOID_SURFACE_SHADING_GLSL
#define PRISMOID_SURFACE_SHADING_GLSL

#include "scene_bindings.glsl"
#include "bsdf.glsl"
#include "area_light.glsl"

struct SurfacePoint {
  vec3 position;   // scene-local
  vec3 geometric;  // unit winding normal, turned towards the viewer (zero for a degenerate triangle)
  vec3 normal;     // unit shading normal on the viewer's side
  vec3 wo;         // unit direction towards the viewer
  bool front;      // the viewer is on the winding normal's side: emission is seen
  uint triangle;   // global triangle index (a point does not light itself)
};

// As the path tracer's shading_point: reflection is two-sided; a shading normal wound against
// the triangle is turned to its side; one facing away from the viewer is replaced by the
// geometric normal. `interpolated_normal` zero means none (flat shading).
SurfacePoint make_surface_point(vec3 position, vec3 winding_normal, vec3 interpolated_normal, vec3 eye, uint triangle) {
  SurfacePoint sp;
  sp.position = position;
  sp.wo = normalize(eye - position);
  sp.triangle = triangle;
  float facing = dot(winding_normal, sp.wo);
  sp.front = facing > 0.0;
  sp.geometric = facing >= 0.0 ? winding_normal : -winding_normal;
  vec3 n = winding_normal;
  float len = length(interpolated_normal);
  if (len > 0.0 && !isinf(len)) n = interpolated_normal / len;
  if (dot(n, sp.geometric) < 0.0) n = -n;
  if (!(dot(n, sp.wo) > 0.0)) n = sp.geometric;
  sp.normal = n;
  return sp;
}

ShadingMaterial shading_material(SurfaceMaterialGpu m, vec3 color) {
  ShadingMaterial s;
  s.albedo = m.albedo.rgb * color;
  s.f0 = m.specular.rgb;
  s.alpha = m.albedo.w;
  s.specular = m.specular.w > 0.0;
  return s;
}

// ---- The shadow hook --------------------------------------------------------------------
// Visibility in [0, 1] of each light from a surface point. Without ray tracing every light is
// fully visible: the image is direct light without shadows, exactly what
// renderer/reference/direct_light.hpp computes and what the tests hold the GPU to. A backend
// with shadows (renderer/rt, shaders/rt) defines PRISMOID_SURFACE_SHADOWS before including this
// file, which then only declares these three functions, and defines them after it:
//  - point_light_visibility / directional_light_visibility: one shadow ray from
//    sp.position offset along sp.geometric (towards the viewer's side) to the light position /
//    along `to_light` to infinity, skipping sp.triangle;
//  - emitter_visibility: the visible fraction of the emitter, which multiplies its closed-form
//    diffuse term and its GGX term; e.g. the ratio estimator of Heitz, Hill & McGuire 2018
//    ("Combining analytic direct illumination and stochastic shadows"): the unshadowed
//    analytic integral times (shadowed / unshadowed) stochastic estimates from shared samples.
//    The emitter's own triangle (info.x) must be skipped by its shadow rays.
// Coordinates: sp.position and the light buffers are relative to GpuSurfaceScene::origin, as
// are the acceleration structure's positions (renderer/rt SceneAccel uses the same origin).
// Fragment shaders do not trace (no ray queries on the GPU machine): shadowed passes are
// ray-generation shaders that rebuild the surface point (surface_point.glsl).
#ifdef PRISMOID_SURFACE_SHADOWS
float point_light_visibility(SurfacePoint sp, uint light, vec3 to_light);
float directional_light_visibility(SurfacePoint sp, uint light, vec3 to_light);
float emitter_visibility(SurfacePoint sp, uint emitter);
#else
float point_light_visibility(SurfacePoint sp, uint light, vec3 to_light) { return 1.0; }
float directional_light_visibility(SurfacePoint sp, uint light, vec3 to_light) { return 1.0; }
float emitter_visibility(SurfacePoint sp, uint emitter) { return 1.0; }
#endif
// -------------------------------------------------------------------------------------------

// f cos for a direction towards a light, zero below the geometric or the shading horizon.
vec3 reflected(SurfacePoint sp, ShadingMaterial m, vec3 wi) {
  if (!(dot(wi, sp.geometric) > 0.0)) return vec3(0.0);
  return bsdf_cos(m, sp.normal, sp.wo, wi);
}

// Le times the GGX lobe's cosine-weighted integral over the polygon's directions: each fan
// triangle cut into N^2 sub-triangles, each weighing the integrand towards its middle by its
// solid angle (PRISMOID_AREA_SPECULAR_SUBDIVISION; the same rule as reference::subdivision_rule).
vec3 emitter_specular(SurfacePoint sp, ShadingMaterial m, PolygonCorners poly, int count, vec3 emission) {
  const int n = int(PRISMOID_AREA_SPECULAR_SUBDIVISION);
  const float inv_n = 1.0 / float(PRISMOID_AREA_SPECULAR_SUBDIVISION);
  float cos_o = dot(sp.normal, sp.wo);
  if (!(cos_o > 0.0)) return vec3(0.0);
  vec3 sum = vec3(0.0);
  for (int k = 1; k + 1 < count; ++k) {
    vec3 a = poly[0];
    vec3 e1 = (poly[k] - a) * inv_n, e2 = (poly[k + 1] - a) * inv_n;
    vec3 edges = cross(e1, e2);  // the same for every sub-triangle, upright or upside down
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j)
        for (int flip = 0; flip < 2; ++flip) {
          if (flip == 1 && i + j + 2 > n) continue;
          vec3 p = a + float(i) * e1 + float(j) * e2;
          vec3 q0 = flip == 0 ? p : p + e1;
          vec3 q1 = flip == 0 ? p + e1 : p + e1 + e2;
          vec3 q2 = p + e2;
          vec3 middle = q0 + q1 + q2;
          float len = length(middle);
          if (!(len > 0.0)) continue;
          vec3 w = middle / len;
          float cos_i = dot(sp.normal, w);
          if (!(cos_i > 0.0) || !(dot(w, sp.geometric) > 0.0)) continue;
          float omega = triangle_solid_angle(q0, q1, q2, edges);
          sum += omega * ggx_specular(m, sp.normal, sp.wo, w, cos_o, cos_i) * cos_i;
        }
  }
  return emission * sum;
}

vec3 emitter_light(SurfacePoint sp, ShadingMaterial m, EmitterGpu e) {
  vec3 p = sp.position;
  // Its back (emitters are one-sided), or its plane within PRISMOID_EMITTER_PLANE_EPSILON.
  float scale = frame.subpixel.z > 0.0 ? frame.subpixel.z : max(max(abs(p.x), abs(p.y)), max(abs(p.z), 1.0));
  if (!(dot(e.normal.xyz, p - e.v0.xyz) > float(PRISMOID_EMITTER_PLANE_EPSILON) * scale)) return vec3(0.0);
  PolygonCorners corners;
  corners[0] = e.v0.xyz - p;
  corners[1] = e.v1.xyz - p;
  corners[2] = e.v2.xyz - p;
  PolygonCorners above_geometric, above_both;
  int count = clip_to_hemisphere(corners, 3, sp.geometric, above_geometric);
  count = clip_to_hemisphere(above_geometric, count, sp.normal, above_both);
  if (count < 3) return vec3(0.0);
  vec3 L = m.albedo * (1.0 / PRISMOID_PI) * e.emission.rgb * projected_solid_angle(above_both, count, sp.normal);
  if (m.specular) L += emitter_specular(sp, m, above_both, count, e.emission.rgb);
  return L;
}

// The sky's cosine-weighted mean radiance over the hemisphere of the unit normal n:
// (top + bottom) / 2 + (top - bottom) dot(up, n) / 3 (reference::sky_cosine_mean).
vec3 sky_cosine_mean(vec3 n) {
  return 0.5 * (frame.sky_top.rgb + frame.sky_bottom.rgb) + (frame.sky_top.rgb - frame.sky_bottom.rgb) * (dot(frame.sky_up.xyz, n) / 3.0);
}

// The light the scene's lights (point, directional, emissive triangles) reflect at the point:
// no emission of its own and no sky. ReSTIR GI (shaders/surface/gi/) uses it for the radiance a
// bounce's hit point sends back.
//
// Every emitter's closed-form term is summed before the first shadow ray is traced; the shadow
// of an emitter then removes (1 - visibility) of its term. Next to a corner where emitters meet,
// the terms of their shared edges cancel only if every emitter sees the very same point (a shift
// of one ulp at 1e-5 from the corner moves a term by 1e-3). In ray-generation code a compiler
// may recompute the point after each traced ray a few ulps away from its first value (`precise`
// does not prevent it), so terms summed between rays would not cancel
// (tests/surface/test_forward.cpp, FurnaceNextToACornerStaysAtTheClosedForm; docs/results.md,
// "The GI furnace's excess"). Fragment shaders trace nothing, and there the second loop folds
// away.
vec3 surface_lights(SurfacePoint sp, ShadingMaterial m) {
  vec3 L = vec3(0.0);
  for (uint i = 0u; i < frame.counts.z; ++i)
    if (emitters[i].info.x != sp.triangle) L += emitter_light(sp, m, emitters[i]);  // a point does not light itself
  for (uint i = 0u; i < frame.counts.x; ++i) {
    vec3 to = point_lights[i].position.xyz - sp.position;
    float d2 = dot(to, to);
    if (!(d2 > 0.0)) continue;
    vec3 wi = to * inversesqrt(d2);
    vec3 fcos = reflected(sp, m, wi);
    if (fcos == vec3(0.0)) continue;
    L += fcos * point_lights[i].intensity.rgb * (point_light_visibility(sp, i, to) / d2);
  }
  for (uint i = 0u; i < frame.counts.y; ++i) {
    vec3 wi = directional_lights[i].to_light.xyz;
    vec3 fcos = reflected(sp, m, wi);
    if (fcos == vec3(0.0)) continue;
    L += fcos * directional_lights[i].irradiance.rgb * directional_light_visibility(sp, i, wi);
  }
  for (uint i = 0u; i < frame.counts.z; ++i) {
    if (emitters[i].info.x == sp.triangle) continue;
    float hidden = 1.0 - emitter_visibility(sp, i);
    if (hidden > 0.0) L -= hidden * emitter_light(sp, m, emitters[i]);
  }
  return max(L, vec3(0.0));  // a whole emitter's term taken back where the point moved an ulp
}

// Emission (front side) + the lights + the sky's ambient term. With ReSTIR GI on, the host sets
// frame.sky_up.w = 1: the sky then reaches the point through GI's bounce rays (with occlusion)
// and its ambient term is left out here (default 0: unchanged).
vec3 shade_surface_point(SurfacePoint sp, ShadingMaterial m, vec3 emission) {
  vec3 L = surface_lights(sp, m);
  if (sp.front) L += emission;
  if (frame.counts.w != 0u && frame.sky_up.w == 0.0) L += m.albedo * sky_cosine_mean(sp.normal);
  return L;
}

#endif
