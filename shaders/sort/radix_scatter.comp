#version 460
// Radix sort, step 5 of each pass: each block sorts its keys by the pass's digit in shared
// memory, stably, then writes every key to the global offset of its (digit, block) plus its
// rank among the block's keys of that digit. Stable within blocks and blocks in order, so
// the pass is stable, which LSD radix sort needs.
//
// The local sort is four stable splits on 2 bits each: one workgroup prefix sum of four
// bucket counters per split gives every key its new place.
#extension GL_GOOGLE_include_directive : require
#include "../shared/sort.h"
#define PRISMOID_SCAN_UVEC4
#include "workgroup_scan.glsl"

layout(local_size_x = PRISMOID_SORT_WORKGROUP_SIZE) in;
layout(set = 0, binding = PRISMOID_SORT_BINDING_KEYS_IN, std430) readonly buffer KeysIn { uint keys_in[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_VALUES_IN, std430) readonly buffer ValuesIn { uint values_in[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_KEYS_OUT, std430) writeonly buffer KeysOut { uint keys_out[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_VALUES_OUT, std430) writeonly buffer ValuesOut { uint values_out[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_HISTOGRAMS, std430) readonly buffer Histograms { uint histograms[]; };
layout(set = 0, binding = PRISMOID_SORT_BINDING_PARAMS, std430) readonly buffer Params { RadixSortParams sort; };
layout(push_constant) uniform Push { RadixSortPush push; };

const uint kItems = PRISMOID_SORT_ITEMS_PER_INVOCATION;
const uint kSplitBits = 2u;

shared uint block_keys[PRISMOID_SORT_BLOCK];
shared uint block_values[PRISMOID_SORT_BLOCK];
shared uint digit_local_start[PRISMOID_SORT_RADIX];   // first place of each digit in the sorted block
shared uint digit_global_start[PRISMOID_SORT_RADIX];  // where the block's first key of each digit goes

uint digit_of(uint key) { return (key >> push.params.y) & (PRISMOID_SORT_RADIX - 1u); }

void main() {
  const uint t = gl_LocalInvocationID.x;
  const uint block = gl_WorkGroupID.x;
  const uint count = sort.counts.x, shift = push.params.y, blocks = sort.counts.z;
  const uint begin = block * PRISMOID_SORT_BLOCK;
  const uint valid = min(PRISMOID_SORT_BLOCK, count - begin);

  digit_global_start[t] = histograms[t * blocks + block];

  // Invocation t holds block places t*kItems .. t*kItems+kItems-1. Places past the end get
  // the largest key: every split sends them to its last bucket, behind the real keys of
  // that bucket (they come later and the split is stable), so the real keys end in
  // places 0 .. valid-1.
  uint k[kItems], v[kItems];
  for (uint i = 0; i < kItems; ++i) {
    const uint index = begin + t * kItems + i;
    k[i] = index < count ? keys_in[index] : 0xFFFFFFFFu;
    v[i] = index < count ? values_in[index] : 0u;
  }

  for (uint bit = 0u; bit < PRISMOID_SORT_RADIX_BITS; bit += kSplitBits) {
    uvec4 mine = uvec4(0u);
    for (uint i = 0; i < kItems; ++i) mine[(k[i] >> (shift + bit)) & 3u] += 1u;
    uvec4 totals;
    const uvec4 before = workgroup_exclusive_sum4(mine, totals);
    uvec4 next = before + uvec4(0u, totals.x, totals.x + totals.y, totals.x + totals.y + totals.z);
    for (uint i = 0; i < kItems; ++i) {
      const uint bucket = (k[i] >> (shift + bit)) & 3u;
      block_keys[next[bucket]] = k[i];
      block_values[next[bucket]] = v[i];
      next[bucket] += 1u;
    }
    barrier();
    for (uint i = 0; i < kItems; ++i) {
      k[i] = block_keys[t * kItems + i];
      v[i] = block_values[t * kItems + i];
    }
    barrier();
  }

  // The sorted block is in block_keys/block_values; a digit starts where it differs from
  // the key before it.
  for (uint i = 0; i < kItems; ++i) {
    const uint place = i * PRISMOID_SORT_WORKGROUP_SIZE + t;
    if (place < valid) {
      const uint digit = digit_of(block_keys[place]);
      if (place == 0u || digit != digit_of(block_keys[place - 1u])) digit_local_start[digit] = place;
    }
  }
  barrier();
  for (uint i = 0; i < kItems; ++i) {
    const uint place = i * PRISMOID_SORT_WORKGROUP_SIZE + t;
    if (place < valid) {
      const uint key = block_keys[place];
      const uint digit = digit_of(key);
      const uint target = digit_global_start[digit] + place - digit_local_start[digit];
      keys_out[target] = key;
      values_out[target] = block_values[place];
    }
  }
}
