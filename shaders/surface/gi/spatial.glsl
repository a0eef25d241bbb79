// ReSTIR GI pass 2, per shading sample: spatial resampling of pass 1's reservoirs of the sample
// and of up to k neighbours (the host's gi_neighbor), shifted by reconnection; biased or
// unbiased (restir_gi.glsl says how). Writes the final reservoir to the sample's slot (next
// frame's history) and to its fallback-layer entry, and the indirect radiance f cos Lo W
// towards the viewer to gi_output[sample]. Include after restir_gi.glsl and the host's hooks.
#ifndef PRISMOID_SURFACE_GI_SPATIAL_GLSL
#define PRISMOID_SURFACE_GI_SPATIAL_GLSL

#define PRISMOID_GI_MAX_NEIGHBOURS 16

void gi_spatial_main() {
  const uint q = gi_launch_sample();
  if (q >= gi_settings.params.y) return;
  GiPoint p = gi_point_of_sample(q);
  uint rng = gi_seed(q, 1u);
  const bool unbiased = gi_unbiased();

  GiResampler s = gi_resampler();
  GiReservoir own = gi_temporal[q];
  float own_target = gi_target(p, own);
  gi_stream(s, own, own_target * own.sample_point.w * own.sample_normal.w, own.sample_normal.w, own_target, 0, rng);

  uint neighbours[PRISMOID_GI_MAX_NEIGHBOURS];
  float neighbour_M[PRISMOID_GI_MAX_NEIGHBOURS];
  uint count = 0u;
  const uint k_max = min(gi_settings.params.w, uint(PRISMOID_GI_MAX_NEIGHBOURS));
  for (uint k = 0u; k < k_max; ++k) {
    uint n;
    if (!gi_neighbor(q, k, rng, n) || n == q || n >= gi_settings.params.y) continue;
    // Geometric similarity (chosen without looking at the samples, so it biases nothing): the
    // neighbours' surfaces within the normal angle limit.
    GiSample ns = gi_samples[n];
    vec3 n_geo = triangles[ns.id.x].normal.xyz;
    if (dot(n_geo, ns.viewer.xyz) < 0.0) n_geo = -n_geo;
    if (!(dot(n_geo, p.sp.geometric) >= gi_settings.limits.z)) continue;
    GiReservoir r = gi_temporal[n];
    float M = r.sample_normal.w;
    float jacobian = gi_shift_jacobian(r, r.origin.xyz, p.sp.position);
    // Biased (as shipped): a neighbour whose sample cannot be shifted here is left out, M and
    // all. Unbiased: it is streamed with weight 0 and Z decides whether its M counts.
    if (!unbiased && jacobian == 0.0 && gi_valid(r)) continue;
    float target = jacobian > 0.0 ? gi_target(p, r) : 0.0, w = 0.0;
    if (target > 0.0) {
      if (unbiased) target *= gi_visible(p, r);
      w = target * r.sample_point.w * M * jacobian;
    }
    gi_stream(s, r, w, M, target, int(count) + 1, rng);
    neighbours[count] = n;
    neighbour_M[count] = M;
    ++count;
  }

  float Z = s.M;
  if (unbiased && s.source >= 0) {
    // x1's own domain holds the chosen sample (its own, or a neighbour's checked visible); each
    // neighbour's domain counts where its x1 could have produced it.
    Z = own.sample_normal.w;
    for (uint c = 0u; c < count; ++c) {
      if (s.source == int(c) + 1) {
        Z += neighbour_M[c];
        continue;
      }
      GiPoint o = gi_point_of_sample(neighbours[c]);
      if (gi_shift_jacobian(s.chosen, o.sp.position, p.sp.position) > 0.0 && gi_target(o, s.chosen) > 0.0 &&
          gi_visible(o, s.chosen) > 0.0)
        Z += neighbour_M[c];
    }
  }
  GiReservoir r = gi_finish(s, Z, p, q);
  gi_slots[gi_slot(q)] = r;
  uint fallback;
  if (gi_fallback_slot(q, fallback)) gi_fallback[fallback] = r;
  vec3 L = gi_fcos(p, r) * r.radiance.rgb * r.sample_point.w;
  gi_output[q] = vec4(L, 0.0);
  if ((gi_settings.params.z & PRISMOID_GI_WRITE_DIRECT) != 0u) gi_direct_output[q] = vec4(shade_surface_point(p.sp, p.m, p.emission), 0.0);
}

#endif
