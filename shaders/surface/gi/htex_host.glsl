// The Htex backend as a ReSTIR GI host (renderer/surface/gi/htex_gi.hpp; Li & Guo 4): the shading
// samples are the texels of this frame's task shadels (HtexPass's task list, 8 x 8 texels per
// task, launched indirectly like the shading pass), and a sample's index IS its physical pool
// slot (page * 4096 + texel in page), so the GI buffers indexed by sample (samples, pass 1's
// reservoirs, the output = HtexPass's indirect buffer) are sized by the pool.
//   gi_slot(q)            = q.
//   gi_history_valid(q)   : the slot's stamp (written by the spatial pass) names this virtual
//                           texel and last frame: a page freed, reassigned or not shaded last
//                           frame invalidates.
//   gi_neighbor(q, k)     : a random offset within GiSettings radius (texels, at most 8),
//                           walked over the surface (htex_walk.glsl, the twin of htex_walk.cpp)
//                           at the sample's level, then the page table: only texels resident and
//                           in a marked shadel (a task this frame) count.
//   gi_fallback_slot(q)   : the persistent layer's texel containing the sample's texel (one
//                           fixed level per mesh, every texel always allocated; see htex_gi.hpp).
// A sample's GiSample::id is (triangle, virtual texel x, virtual texel y, 1); the samples pass
// (htex_samples.rgen) writes it. Include after restir_gi.glsl (with PRISMOID_GI_HOST_LAUNCH).
#ifndef PRISMOID_SURFACE_GI_HTEX_HOST_GLSL
#define PRISMOID_SURFACE_GI_HTEX_HOST_GLSL

#include "htex_host_common.glsl"

uint gi_slot(uint sample_index) { return sample_index; }

bool gi_history_valid(uint sample_index) {
  uvec4 stamp = gi_htex_stamps[sample_index];
  return stamp.z == gi_settings.params.x && stamp.z != 0u && stamp.xy == gi_samples[sample_index].id.yz;
}

bool gi_neighbor(uint sample_index, uint k, inout uint rng, out uint neighbor_sample) {
  neighbor_sample = 0u;
  float u = gi_random(rng);
  int radius = min(int(max(gi_settings.limits.y, 0.0)), 8);
  if (radius == 0) return false;
  uvec2 v = gi_samples[sample_index].id.yz;
  HtexTexelAddress t;
  if (!htex_texel_at(v, t)) return false;
  uint span = uint(2 * radius + 1), cells = span * span - 1u;
  uint pick = min(uint(u * float(cells)), cells - 1u);
  if (pick >= cells / 2u) ++pick;  // skip the centre
  ivec2 offset = ivec2(int(pick % span), int(pick / span)) - ivec2(radius);
  uint n = htex_side(t.mesh, t.level);
  HtexQuadTexel to;
  if (!htex_walk_texel(n, HtexQuadTexel(t.quad, ivec2(t.i, t.j)), offset, to)) return false;
  uvec2 w = htex_virtual_texel(t.mesh, to.edge, t.level, uint(to.ij.x), uint(to.ij.y));
  uint slot;
  if (!gi_htex_task_slot(w, slot)) return false;
  neighbor_sample = slot;
  return true;
}

bool gi_fallback_slot(uint sample_index, out uint slot) {
  slot = 0u;
  HtexTexelAddress t;
  if (!htex_texel_at(gi_samples[sample_index].id.yz, t)) return false;
  uvec4 layer = gi_htex_layers[t.mesh];  // x: first entry, y: level, z: side
  if (layer.z == 0u) return false;
  uint i = t.i, j = t.j;
  if (t.level <= layer.y) {
    uint s = layer.y - t.level;
    i >>= s;
    j >>= s;
  } else {
    uint s = t.level - layer.y;
    i = (i << s) + ((1u << s) >> 1u);
    j = (j << s) + ((1u << s) >> 1u);
  }
  uint local = t.quad - htex_meshes[t.mesh].info.x;
  slot = layer.x + (local * layer.z + j) * layer.z + i;
  return true;
}

uint gi_launch_sample() {
  uvec2 v;
  uint slot;
  if (!gi_htex_launch_texel(v, slot)) return 0xffffffffu;
  return slot;
}

#endif
