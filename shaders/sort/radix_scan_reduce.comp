#version 460
// Radix sort, step 2 of each pass (reduce-then-scan of the histograms): the sum of each
// scan block of histogram entries.
#extension GL_GOOGLE_include_directive : require
#include "../shared/sort.h"
#define PRISMOID_SCAN_UINT
#include "workgroup_scan.glsl"

layout(local_size_x = PRISMOID_SORT_WORKGROUP_SIZE) in;
layout(set = 0, binding = PRISMOID_SORT_BINDING_HISTOGRAMS, std430) readonly buffer Histograms { uint histograms[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARTIALS, std430) writeonly buffer Partials { uint partials[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARAMS, std430) readonly buffer Params { RadixSortParams sort; };
layout(push_constant) uniform Push { RadixSortPush push; };

void main() {
  const uint entries = sort.counts.w;
  const uint base = gl_WorkGroupID.x * PRISMOID_SORT_SCAN_BLOCK + gl_LocalInvocationID.x * PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION;
  uint sum = 0u;
  for (uint i = 0; i < PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION; ++i)
    if (base + i < entries) sum += histograms[base + i];
  uint total;
  workgroup_exclusive_sum(sum, total);
  if (gl_LocalInvocationID.x == 0u) partials[gl_WorkGroupID.x] = total;
}
