#version 460
// Radix sort, step 1 of each pass: how many keys of each digit every block holds.
#extension GL_GOOGLE_include_directive : require
#include "../shared/sort.h"

layout(local_size_x = PRISMOID_SORT_WORKGROUP_SIZE) in;
layout(set = 0, binding = PRISMOID_SORT_BINDING_KEYS_IN, std430) readonly buffer KeysIn { uint keys_in[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_HISTOGRAMS, std430) writeonly buffer Histograms { uint histograms[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARAMS, std430) readonly buffer Params { RadixSortParams sort; };
layout(push_constant) uniform Push { RadixSortPush push; };

shared uint digit_count[PRISMOID_SORT_RADIX];

void main() {
  const uint t = gl_LocalInvocationID.x;
  const uint block = gl_WorkGroupID.x;
  const uint count = sort.counts.x, shift = push.params.y, blocks = sort.counts.z;
  digit_count[t] = 0u;
  barrier();
  const uint begin = block * PRISMOID_SORT_BLOCK;
  for (uint i = 0; i < PRISMOID_SORT_ITEMS_PER_INVOCATION; ++i) {
    const uint index = begin + i * PRISMOID_SORT_WORKGROUP_SIZE + t;
    if (index < count) atomicAdd(digit_count[(keys_in[index] >> shift) & (PRISMOID_SORT_RADIX - 1u)], 1u);
  }
  barrier();
  histograms[t * blocks + block] = digit_count[t];
}
