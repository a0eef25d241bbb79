#version 460
// Radix sort, step 4 of each pass: each scan block's histogram entries become their global
// exclusive prefix (its own prefix plus the block's scanned partial sum), so entry
// digit * blocks + block is where that block's first key of that digit goes.
#extension GL_GOOGLE_include_directive : require
#include "../shared/sort.h"
#define PRISMOID_SCAN_UINT
#include "workgroup_scan.glsl"

layout(local_size_x = PRISMOID_SORT_WORKGROUP_SIZE) in;
layout(set = 0, binding = PRISMOID_SORT_BINDING_HISTOGRAMS, std430) buffer Histograms { uint histograms[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARTIALS, std430) readonly buffer Partials { uint partials[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARAMS, std430) readonly buffer Params { RadixSortParams sort; };
layout(push_constant) uniform Push { RadixSortPush push; };

void main() {
  const uint entries = sort.counts.w;
  const uint base = gl_WorkGroupID.x * PRISMOID_SORT_SCAN_BLOCK + gl_LocalInvocationID.x * PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION;
  uint v[PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION];
  uint sum = 0u;
  for (uint i = 0; i < PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION; ++i) {
    v[i] = base + i < entries ? histograms[base + i] : 0u;
    sum += v[i];
  }
  uint total;
  uint running = partials[gl_WorkGroupID.x] + workgroup_exclusive_sum(sum, total);
  for (uint i = 0; i < PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION; ++i) {
    if (base + i < entries) histograms[base + i] = running;
    running += v[i];
  }
}
