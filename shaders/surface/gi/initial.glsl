// ReSTIR GI pass 1, per shading sample: one new candidate (a cosine-sampled bounce ray) and
// temporal resampling with the reservoir of the sample's slot (last frame's final reservoir, M
// capped), or with the fallback layer's reservoir when the history is invalid. Writes the
// result to gi_temporal[sample] for pass 2. Include after restir_gi.glsl and the host's hooks.
#ifndef PRISMOID_SURFACE_GI_INITIAL_GLSL
#define PRISMOID_SURFACE_GI_INITIAL_GLSL

// Cosine-weighted direction about the unit normal n (Malley's method on a frame from Duff et
// al. 2017).
vec3 gi_cosine_direction(vec3 n, float u1, float u2) {
  float sign_z = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (sign_z + n.z);
  float b = n.x * n.y * a;
  vec3 t = vec3(1.0 + sign_z * n.x * n.x * a, sign_z * b, -sign_z * n.x);
  vec3 bt = vec3(b, sign_z + n.y * n.y * a, -n.y);
  float r = sqrt(u1), phi = 2.0 * PRISMOID_PI * u2;
  float z = sqrt(max(0.0, 1.0 - u1));
  return normalize(r * cos(phi) * t + r * sin(phi) * bt + z * n);
}

// A fresh candidate from x1: the bounce ray's hit (its direct light towards x1) or the sky.
GiReservoir gi_new_candidate(GiPoint p, inout uint rng, out float pdf) {
  GiResampler empty = gi_resampler();
  GiReservoir c = empty.chosen;
  float u1 = gi_random(rng), u2 = gi_random(rng);
  // The direction as the reservoir keeps it (octahedral, a few ulps from the sampled one) is the
  // one traced, and its pdf cos / pi takes the cosine the target takes (reflected): in target /
  // pdf the two cancel to rounding, where the sampled z would differ from it by ~1e-7 / z.
  vec2 encoded = gi_oct_encode(gi_cosine_direction(p.sp.normal, u1, u2));
  vec3 wi = gi_oct_decode(encoded);
  pdf = dot(p.sp.normal, wi) * (1.0 / PRISMOID_PI);
  if (!(dot(wi, p.sp.geometric) > 0.0) || !(pdf > 0.0)) {
    pdf = 0.0;  // below the geometric surface: no reflection (the path tracer ends such paths too)
    return c;
  }
  vec3 origin = offset_ray_origin(p.sp.position, p.sp.geometric);
  gi_hit.hit = vec4(-1.0, 0.0, 0.0, 0.0);
  gi_hit.id = uvec4(0u);
  traceRayEXT(scene_tlas, gl_RayFlagsOpaqueEXT, 0xFF, PRISMOID_SURFACE_HIT_GROUP, 0, PRISMOID_SURFACE_MISS_HIT, origin, 0.0, wi,
              uintBitsToFloat(0x7f7fffffu), PRISMOID_SURFACE_PAYLOAD_HIT);
  c.origin = vec4(p.sp.position, 0.0);  // the traced direction is kept for this x1 (gi_direction)
  c.origin_bary.zw = encoded;
  if (gi_hit.id.y == 0u) {
    c.sample_point = vec4(wi, 0.0);
    c.radiance = vec4(gi_sky_radiance(wi), 0.0);
    c.info.z = PRISMOID_GI_SAMPLE_VALID | PRISMOID_GI_SAMPLE_SKY;
    return c;
  }
  uint triangle = gi_hit.id.x;
  vec3 bary = vec3(1.0 - gi_hit.hit.y - gi_hit.hit.z, gi_hit.hit.y, gi_hit.hit.z);
  vec3 x2 = triangle_point(triangle, bary);
  // x2 seen along the ray (eye = x2 - wi): its side is the ray's, even where x1 lies in x2's
  // plane (a ray from a concave edge or vertex hitting the next face at once).
  ShadingInput s = shading_input_at(triangle, bary, x2, x2 - wi);
  c.sample_point = vec4(x2, 0.0);
  c.sample_normal = vec4(s.point.geometric, 0.0);
  c.radiance = vec4(surface_lights(s.point, s.material), 0.0);
  c.info.z = s.point.geometric == vec3(0.0) ? 0u : PRISMOID_GI_SAMPLE_VALID;
  return c;
}

void gi_initial_main() {
  const uint q = gi_launch_sample();
  if (q >= gi_settings.params.y) return;
  const uint flags = gi_settings.params.z;
  GiPoint p = gi_point_of_sample(q);
  uint rng = gi_seed(q, 0u);
  GiResampler s = gi_resampler();
  bool fresh = (flags & PRISMOID_GI_NO_INITIAL) == 0u;
  if (fresh) {
    float pdf;
    GiReservoir c = gi_new_candidate(p, rng, pdf);
    float target = pdf > 0.0 ? gi_target(p, c) : 0.0;
    gi_stream(s, c, pdf > 0.0 ? target / pdf : 0.0, 1.0, target, 0, rng);
  }

  // The history: this slot's reservoir, or the fallback layer's.
  bool have_prev = false;
  GiReservoir prev;
  if ((flags & PRISMOID_GI_TEMPORAL) != 0u) {
    uint fallback;
    if (gi_history_valid(q)) {
      prev = gi_slots[gi_slot(q)];
      have_prev = true;
    } else if ((flags & PRISMOID_GI_FALLBACK) != 0u && gi_fallback_slot(q, fallback)) {
      prev = gi_fallback[fallback];
      have_prev = true;
    }
  }
  bool shifted = false;
  float prev_M = 0.0;
  if (have_prev && !gi_unbiased() && gi_valid(prev) && gi_shift_jacobian(prev, prev.origin.xyz, p.sp.position) == 0.0)
    have_prev = false;  // biased: a history that cannot be shifted here is left out, M and all
  if (have_prev) {
    prev_M = min(prev.sample_normal.w, gi_settings.limits.x);
    shifted = prev.origin.xyz != p.sp.position;
    float jacobian = gi_shift_jacobian(prev, prev.origin.xyz, p.sp.position);
    float target = jacobian > 0.0 ? gi_target(p, prev) : 0.0, w = 0.0;
    if (target > 0.0) {
      if (shifted && gi_unbiased()) target *= gi_visible(p, prev);
      w = target * prev.sample_point.w * prev_M * jacobian;
    }
    gi_stream(s, prev, w, prev_M, target, 1, rng);
    if (s.source == 1) s.chosen.info.y += 1u;  // one frame older
  }

  float Z = s.M;
  if (gi_unbiased() && shifted && s.source >= 0) {
    // The fresh candidate's domain (x1's visible hemisphere) holds the chosen sample: a history
    // sample was chosen only if visible from x1. The history's domain is its own x1's.
    Z = fresh ? 1.0 : 0.0;
    if (s.source == 1) {
      Z += prev_M;
    } else {
      GiPoint o = gi_point(prev.info.x, prev.origin_bary.xy, prev.origin.xyz, p.sp.wo);
      if (gi_shift_jacobian(s.chosen, o.sp.position, p.sp.position) > 0.0 && gi_target(o, s.chosen) > 0.0 &&
          gi_visible(o, s.chosen) > 0.0)
        Z += prev_M;
    }
  }
  gi_temporal[q] = gi_finish(s, Z, p, q);
}

#endif
