#version 460
// Radix sort, step 3 of each pass: one workgroup turns the scan blocks' sums into their
// exclusive prefix, a tile of SCAN_BLOCK sums at a time (a 16M-key sort has 4096 of them).
#extension GL_GOOGLE_include_directive : require
#include "../shared/sort.h"
#define PRISMOID_SCAN_UINT
#include "workgroup_scan.glsl"

layout(local_size_x = PRISMOID_SORT_WORKGROUP_SIZE) in;
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARTIALS, std430) buffer Partials { uint partials[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARAMS, std430) readonly buffer Params { RadixSortParams sort; };
layout(push_constant) uniform Push { RadixSortPush push; };

void main() {
  const uint n = (sort.counts.w + PRISMOID_SORT_SCAN_BLOCK - 1u) / PRISMOID_SORT_SCAN_BLOCK;
  uint carry = 0u;
  for (uint tile = 0u; tile < n; tile += PRISMOID_SORT_SCAN_BLOCK) {
    const uint base = tile + gl_LocalInvocationID.x * PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION;
    uint v[PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION];
    uint sum = 0u;
    for (uint i = 0; i < PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION; ++i) {
      v[i] = base + i < n ? partials[base + i] : 0u;
      sum += v[i];
    }
    uint total;
    uint running = carry + workgroup_exclusive_sum(sum, total);
    for (uint i = 0; i < PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION; ++i) {
      if (base + i < n) partials[base + i] = running;
      running += v[i];
    }
    carry += total;
  }
}
