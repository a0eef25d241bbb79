// ReSTIR GI in object space: the pieces both passes share (Ouyang et al. 2021, "ReSTIR GI: Path
// Resampling for Real-Time Path Tracing"; reservoirs live with the shading samples as in Li &
// Guo, "Real-time Seamless Object Space Shading", section 4.2). Included by a host's
// ray-generation shaders (e.g. dense_initial.rgen):
//
//   #include "restir_gi.glsl"        // this file: bindings, reservoirs, target, Jacobian, hooks declared
//   #include "<host hooks>.glsl"     // the host defines the four hooks below
//   #include "initial.glsl" or "spatial.glsl"; void main() { gi_initial_main(); } / gi_spatial_main()
//
// Hooks a host provides (its data from binding PRISMOID_GI_BINDING_HOST on):
//   uint gi_slot(uint sample)
//       The reservoir slot of a sample in the persistent slot buffer (Htex: its physical texel).
//   bool gi_history_valid(uint sample)
//       Whether the slot holds this sample's reservoir from last frame; false after a
//       disocclusion or a fresh allocation of the slot.
//   bool gi_neighbor(uint sample, uint k, inout uint rng, out uint neighbor_sample)
//       The k-th spatial candidate (k < GiSettings neighbours) of a sample, drawn with rng,
//       within GiSettings radius; false when there is none this time (e.g. the walk left the
//       surface). Htex: walk the halfedge adjacency in quad space.
//   bool gi_fallback_slot(uint sample, out uint slot)
//       The sample's entry in the persistent fallback layer (Htex: the finest level's texel
//       holding the point), or false when it has none.
//
// What GI computes. For a sample x1 with viewer direction wo, the one-bounce indirect light
//   L_ind(x1, wo) = integral over the hemisphere of f(wo, wi) cos(wi) Lo(x2(wi) -> x1) dwi,
// where x2 is what a ray from x1 along wi hits and Lo its direct light (surface_lights in
// shading.glsl: lights with shadow rays, without x2's own emission, which x1's direct light
// already counts, and without sky ambient), or the sky's radiance when the ray escapes. The
// host adds L_ind to x1's direct shading (with frame.sky_up.w = 1 so that the sky is not
// counted twice). Together they converge to the path tracer's radiance with max_bounces = 2
// (renderer/reference/path_tracer.hpp radiance_leaving) up to: the shadow approximation of
// area lights (shadow_rays.glsl), and the sky reflected twice (left out).
//
// Resampling. Target p^(x2) = luminance(f cos Lo) at x1; candidates are weighted by
// p^ W M (W: a reservoir's unbiased contribution weight, 1 / pdf for a fresh sample), shifted
// between samples by reconnection (x2 kept) with the solid-angle Jacobian
//   |J| = (cos phi_to / cos phi_from) (|x1_from - x2|^2 / |x1_to - x2|^2),
// phi the angle at x2 between its normal and the direction to x1 (Ouyang et al., eq. 11). A
// reservoir's Lo was computed towards its original x1: reusing it elsewhere is exact for a
// diffuse x2 (the paper's approximation for glossy x2). A sample seen from behind x2's surface
// has p^ = 0. Biased mode (as the paper and Li & Guo ship): W = w_sum / (p^(y) sum M). Unbiased
// mode: a shifted candidate's p^ includes its visibility from x1 (a shadow ray), and
// W = w_sum / (p^(y) Z), Z = the sum of M over the reservoirs whose own x1 could have produced
// y (p^ there > 0 and x2 visible from there; Bitterli et al. 2020 Alg. 6, Ouyang et al. Alg. 4).
#ifndef PRISMOID_SURFACE_GI_RESTIR_GLSL
#define PRISMOID_SURFACE_GI_RESTIR_GLSL

#extension GL_EXT_ray_tracing : require

#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../shadow_rays.glsl"
#include "../surface_point.glsl"
#include "../../shared/gi.h"

layout(push_constant) uniform GiPush { GiSettings gi_settings; };
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_SAMPLES) readonly buffer GiSampleBuffer { GiSample gi_samples[]; };
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_SLOTS) buffer GiSlotBuffer { GiReservoir gi_slots[]; };
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_TEMPORAL) buffer GiTemporalBuffer { GiReservoir gi_temporal[]; };
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_FALLBACK) buffer GiFallbackBuffer { GiReservoir gi_fallback[]; };
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_OUTPUT) writeonly buffer GiOutputBuffer { vec4 gi_output[]; };
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_DIRECT) writeonly buffer GiDirectBuffer { vec4 gi_direct_output[]; };

layout(location = PRISMOID_SURFACE_PAYLOAD_HIT) rayPayloadEXT SurfaceHitPayload gi_hit;

// ---- The host's hooks (defined by the host after this file) --------------------------------
uint gi_slot(uint sample_index);
bool gi_history_valid(uint sample_index);
bool gi_neighbor(uint sample_index, uint k, inout uint rng, out uint neighbor_sample);
bool gi_fallback_slot(uint sample_index, out uint slot);
// The sample this invocation handles (>= GiSettings sample count: none). By default the 2D
// launch index, row by row; a host that launches otherwise (Htex: 8 x 8 texels per task shadel,
// indirectly) defines PRISMOID_GI_HOST_LAUNCH before including this file and defines it.
#ifdef PRISMOID_GI_HOST_LAUNCH
uint gi_launch_sample();
#else
uint gi_launch_sample() { return gl_LaunchIDEXT.y * gl_LaunchSizeEXT.x + gl_LaunchIDEXT.x; }
#endif

// ---- Random numbers -----------------------------------------------------------------------
// A PCG-style integer hash (O'Neill's PCG output permutation on one LCG step).
uint gi_hash(uint x) {
  uint state = x * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
// Uniform in [0, 1).
float gi_random(inout uint rng) {
  rng = gi_hash(rng);
  return float(rng >> 8) * (1.0 / 16777216.0);
}
uint gi_seed(uint sample_index, uint pass) { return gi_hash(sample_index ^ gi_hash(gi_settings.params.x * 4u + pass)); }

// ---- Samples and their shading --------------------------------------------------------------
bool gi_unbiased() { return (gi_settings.params.z & PRISMOID_GI_UNBIASED) != 0u; }
float gi_luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// x1 as the shading code sees it.
struct GiPoint {
  SurfacePoint sp;
  ShadingMaterial m;
  vec3 emission;
};
GiPoint gi_point(uint triangle, vec2 b12, vec3 position, vec3 viewer) {
  ShadingInput s = shading_input_at(triangle, vec3(1.0 - b12.x - b12.y, b12.x, b12.y), position, position + viewer);
  GiPoint p;
  p.sp = s.point;
  p.m = s.material;
  p.emission = s.emission;
  return p;
}
GiPoint gi_point_of_sample(uint sample_index) {
  GiSample s = gi_samples[sample_index];
  return gi_point(s.id.x, vec2(s.position.w, s.viewer.w), s.position.xyz, s.viewer.xyz);
}

vec3 gi_sky_radiance(vec3 direction) {
  float t = 0.5 * (1.0 + dot(direction, frame.sky_up.xyz));
  return frame.sky_bottom.rgb + (frame.sky_top.rgb - frame.sky_bottom.rgb) * t;
}

// Octahedral encoding of unit vectors (Cigolle et al. 2014, "A Survey of Efficient
// Representations for Independent Unit Vectors").
vec2 gi_oct_encode(vec3 v) {
  vec2 p = v.xy / (abs(v.x) + abs(v.y) + abs(v.z));
  if (v.z < 0.0) p = (1.0 - abs(p.yx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
  return p;
}
vec3 gi_oct_decode(vec2 e) {
  vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
  return normalize(v);
}

bool gi_valid(GiReservoir r) { return (r.info.z & PRISMOID_GI_SAMPLE_VALID) != 0u; }
bool gi_sky(GiReservoir r) { return (r.info.z & PRISMOID_GI_SAMPLE_SKY) != 0u; }

// The unit direction from x1 to the reservoir's sample; false when the sample cannot light x1
// by reconnection (no sample, x1 on x2 or behind x2's surface).
bool gi_direction(GiReservoir r, vec3 x1, out vec3 wi, out float dist) {
  wi = vec3(0.0);
  dist = 0.0;
  if (!gi_valid(r)) return false;
  if (gi_sky(r)) {
    wi = r.sample_point.xyz;
    dist = uintBitsToFloat(0x7f7fffffu);
    return true;
  }
  vec3 d = r.sample_point.xyz - x1;
  float len = length(d);
  dist = len;
  if (r.origin.xyz == x1) {
    wi = gi_oct_decode(r.origin_bary.zw);  // the traced direction itself
  } else {
    if (!(len > 0.0) || isinf(len)) return false;
    wi = d / len;
  }
  return dot(r.sample_normal.xyz, wi) < 0.0;
}

// f cos at x1 towards the sample (0 when it cannot light x1).
vec3 gi_fcos(GiPoint p, GiReservoir r) {
  vec3 wi;
  float dist;
  if (!gi_direction(r, p.sp.position, wi, dist)) return vec3(0.0);
  return reflected(p.sp, p.m, wi);
}
float gi_target(GiPoint p, GiReservoir r) { return gi_luminance(gi_fcos(p, r) * r.radiance.rgb); }

// 1 when nothing lies between x1 and the sample (for a sky sample: nothing along its direction).
float gi_visible(GiPoint p, GiReservoir r) {
  vec3 origin = offset_ray_origin(p.sp.position, p.sp.geometric);
  if (gi_sky(r)) return trace_shadow(origin, r.sample_point.xyz, 0.0, uintBitsToFloat(0x7f7fffffu));
  vec3 to = r.sample_point.xyz - origin;
  float d = length(to);
  if (!(d > 0.0)) return 0.0;
  return trace_shadow(origin, to / d, 0.0, d * (1.0 - 1.0e-4));
}

// |J| of moving the reservoir's sample from x1 = `from` to x1 = `to` (1 for the same point or a
// sky sample; 0 where it is not finite).
float gi_jacobian(GiReservoir r, vec3 from, vec3 to) {
  if (gi_sky(r) || from == to) return 1.0;
  vec3 x2 = r.sample_point.xyz, n2 = r.sample_normal.xyz;
  vec3 a = from - x2, b = to - x2;
  float a2 = dot(a, a), b2 = dot(b, b);
  float cos_a = abs(dot(n2, a)) * inversesqrt(a2);
  float cos_b = abs(dot(n2, b)) * inversesqrt(b2);
  float j = (cos_b * a2) / (cos_a * b2);
  return (j > 0.0 && !isinf(j) && !isnan(j)) ? j : 0.0;
}

// The shift's Jacobian where the shift is allowed, else 0. Near a concave edge or vertex a
// bounce from one sample can land arbitrarily close to another, and the Jacobian (|x1_from -
// x2|^2 / |x1_to - x2|^2) becomes unbounded: the estimator's variance with it. Shifts whose
// Jacobian lies outside [1 / tau, tau] (tau = GiSettings limits.w) are not made, in both
// directions alike, so the unbiased mode's count Z can apply the same rule: a reservoir counts
// only where the shift from it would have been made. The reservoir's own x1 is never shifted.
float gi_shift_jacobian(GiReservoir r, vec3 from, vec3 to) {
  float j = gi_jacobian(r, from, to);
  float tau = gi_settings.limits.w;
  return (j >= 1.0 / tau && j <= tau) ? j : 0.0;
}

// ---- Reservoirs -----------------------------------------------------------------------------
// Streaming resampling (weighted reservoir sampling over candidates that are reservoirs).
struct GiResampler {
  GiReservoir chosen;
  float w_sum;
  float M;
  float target;  // p^ of the chosen sample at x1
  int source;    // which candidate was chosen (-1: none)
};
GiResampler gi_resampler() {
  GiResampler s;
  s.chosen.sample_point = vec4(0.0);
  s.chosen.sample_normal = vec4(0.0);
  s.chosen.radiance = vec4(0.0);
  s.chosen.origin = vec4(0.0);
  s.chosen.origin_bary = vec4(0.0);
  s.chosen.info = uvec4(0u);
  s.w_sum = 0.0;
  s.M = 0.0;
  s.target = 0.0;
  s.source = -1;
  return s;
}
void gi_stream(inout GiResampler s, GiReservoir c, float w, float M, float target, int source, inout uint rng) {
  s.M += M;
  float u = gi_random(rng);  // drawn for every candidate: the streams do not depend on the weights
  if (!(w > 0.0) || isinf(w)) return;
  s.w_sum += w;
  if (u * s.w_sum <= w) {
    s.chosen = c;
    s.target = target;
    s.source = source;
  }
}
// The resampled reservoir for x1 = p, normalized by Z (the count of candidates whose domain
// covers the chosen sample; sum M in biased mode).
GiReservoir gi_finish(GiResampler s, float Z, GiPoint p, uint sample_index) {
  GiReservoir r = s.chosen;
  GiSample smp = gi_samples[sample_index];
  vec3 wi;
  float dist;
  bool reaches = gi_direction(r, p.sp.position, wi, dist);  // before the origin moves to x1
  bool some = s.source >= 0 && s.target > 0.0 && Z > 0.0;
  float W = some ? s.w_sum / (Z * s.target) : 0.0;
  if (isinf(W) || isnan(W)) W = 0.0;
  if (!some) r.info.z = 0u;
  r.sample_point.w = W;
  r.sample_normal.w = s.M;
  r.radiance.w = s.w_sum;
  // A direction already kept for this x1 is kept as it is (encoding its decoding again would
  // move it by an ulp, and the target with it).
  vec2 direction = !reaches ? vec2(0.0) : r.origin.xyz == p.sp.position ? r.origin_bary.zw : gi_oct_encode(wi);
  r.origin = vec4(p.sp.position, some ? s.target : 0.0);
  r.origin_bary = vec4(smp.position.w, smp.viewer.w, direction);
  r.info.x = smp.id.x;
  return r;
}

#endif
