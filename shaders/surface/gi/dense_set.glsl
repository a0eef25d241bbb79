// The dense sample set's hooks for ReSTIR GI (renderer/surface/gi/gi_dense_set.hpp): sample i's
// slot and fallback entry are i; history validity is a per-sample flag the host writes; spatial
// candidates come from a precomputed table of texels reached by walking the halfedge adjacency
// in quad space, in rings of growing radius (the first (2 rho + 1)^2 - 1 entries lie within
// radius rho). Include after restir_gi.glsl.
#ifndef PRISMOID_SURFACE_GI_DENSE_SET_GLSL
#define PRISMOID_SURFACE_GI_DENSE_SET_GLSL

layout(std430, set = 0, binding = PRISMOID_GI_BINDING_HOST) readonly buffer GiDenseHistory { uint gi_dense_history[]; };
layout(std430, set = 0, binding = PRISMOID_GI_BINDING_HOST + 1) readonly buffer GiDenseNeighbours {
  uvec4 gi_dense_table_info;  // x: entries per sample, y: the table's largest radius
  uint gi_dense_neighbours[];
};

uint gi_slot(uint sample_index) { return sample_index; }

bool gi_history_valid(uint sample_index) { return gi_dense_history[sample_index] != 0u; }

bool gi_neighbor(uint sample_index, uint k, inout uint rng, out uint neighbor_sample) {
  neighbor_sample = 0u;
  uint radius = min(uint(max(gi_settings.limits.y, 0.0)), gi_dense_table_info.y);
  uint entries = (2u * radius + 1u) * (2u * radius + 1u) - 1u;
  float u = gi_random(rng);
  if (entries == 0u) return false;
  uint pick = min(uint(u * float(entries)), entries - 1u);
  neighbor_sample = gi_dense_neighbours[sample_index * gi_dense_table_info.x + pick];
  return neighbor_sample != 0xFFFFFFFFu;
}

bool gi_fallback_slot(uint sample_index, out uint slot) {
  slot = sample_index;
  return true;
}

#endif
