#version 460
// Radix sort with its key count in device memory (GpuRadixSort::record_indirect): one
// invocation turns the count another pass wrote into the sort's parameters and the group
// counts of its indirect dispatches, so a count made on the GPU needs no read back. Counts
// beyond the capacity the sort's buffers hold are cut to it.
#extension GL_GOOGLE_include_directive : require
#include "../shared/sort.h"

layout(local_size_x = 1) in;
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARAMS, std430) writeonly buffer Params { RadixSortParams sort; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_COUNT, std430) readonly buffer Count { uint count_source[]; };
layout(push_constant) uniform Push { RadixSetupPush push; };

void main() {
  const uint count = min(count_source[push.params.x], push.params.y);
  const uint blocks = (count + PRISMOID_SORT_BLOCK - 1u) / PRISMOID_SORT_BLOCK;
  const uint entries = blocks * PRISMOID_SORT_RADIX;
  const uint scan_groups = (entries + PRISMOID_SORT_SCAN_BLOCK - 1u) / PRISMOID_SORT_SCAN_BLOCK;
  sort.counts = uvec4(count, 0u, blocks, entries);
  // Fewer than two keys are sorted already: no workgroup runs (a zero-size dispatch is valid).
  const bool work = count > 1u;
  sort.block_dispatch = uvec4(work ? blocks : 0u, 1u, 1u, 0u);
  sort.scan_dispatch = uvec4(work ? scan_groups : 0u, 1u, 1u, 0u);
}
