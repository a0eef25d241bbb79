// Layouts shared by the GPU radix sort (shaders/sort/), the visibility keys pass
// (shaders/volume/sort_keys.comp) and renderer/volume/visibility_sort.cpp.
#ifndef PRISMOID_SHARED_SORT_H
#define PRISMOID_SHARED_SORT_H
#include "common.h"

PRISMOID_SHARED_BEGIN

// One radix digit per pass: 4 passes of 8 bits sort 32-bit keys, and an even pass count
// leaves the result in the caller's buffers after ping-ponging through scratch.
#define PRISMOID_SORT_RADIX_BITS 8
#define PRISMOID_SORT_RADIX 256
#define PRISMOID_SORT_PASSES 4
// Invocations per workgroup of every sort kernel. Equal to the radix so that the histogram
// and scatter kernels give each invocation one digit's counter.
#define PRISMOID_SORT_WORKGROUP_SIZE 256
// Keys per invocation in the histogram, scatter and keys kernels, hence keys per block.
#define PRISMOID_SORT_ITEMS_PER_INVOCATION 4
#define PRISMOID_SORT_BLOCK (PRISMOID_SORT_WORKGROUP_SIZE * PRISMOID_SORT_ITEMS_PER_INVOCATION)
// Histogram entries one scan workgroup reduces and then scans (4 per invocation).
#define PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION 4
#define PRISMOID_SORT_SCAN_BLOCK (PRISMOID_SORT_WORKGROUP_SIZE * PRISMOID_SORT_SCAN_ITEMS_PER_INVOCATION)

// Descriptor bindings of set 0 of every radix-sort kernel (each kernel declares those it uses).
#define PRISMOID_SORT_BINDING_KEYS_IN 0     // readonly uint[]
#define PRISMOID_SORT_BINDING_VALUES_IN 1   // readonly uint[]
#define PRISMOID_SORT_BINDING_KEYS_OUT 2    // uint[]
#define PRISMOID_SORT_BINDING_VALUES_OUT 3  // uint[]
// uint[RADIX * blocks], digit-major (entry digit * blocks + block): the count of each digit
// in each block, then, scanned in place, where that block's keys of that digit go.
#define PRISMOID_SORT_BINDING_HISTOGRAMS 4
// uint[ceil(RADIX * blocks / SCAN_BLOCK)]: the sum of each scan workgroup's entries, then
// their exclusive prefix.
#define PRISMOID_SORT_BINDING_PARTIALS 5
// RadixSortParams: how many keys this sort has, read by every kernel. Written by the CPU
// (vkCmdUpdateBuffer) when the count is known there, or by radix_setup.comp from a count
// another pass left in device memory (GpuRadixSort::record_indirect), so a count made on the
// GPU is never read back.
#define PRISMOID_SORT_BINDING_PARAMS 6
// readonly uint[]: where radix_setup.comp reads the count (RadixSetupPush.params.x: its index).
#define PRISMOID_SORT_BINDING_COUNT 7

// Descriptor bindings of set 0 of the visibility keys pass.
#define PRISMOID_SORT_KEYS_BINDING_POSITIONS 0  // readonly vec4[]: xyz in the mesh's local frame
#define PRISMOID_SORT_KEYS_BINDING_TETS 1       // readonly uvec4[]: four point indices per cell
#define PRISMOID_SORT_KEYS_BINDING_KEYS 2       // writeonly uint[]
#define PRISMOID_SORT_KEYS_BINDING_VALUES 3     // writeonly uint[]

struct RadixSortPush {
  uvec4 params;  // x: unused, y: shift of this pass's digit, z, w: unused
};

// The sort's size, in device memory, followed by the indirect dispatches it needs
// (VkDispatchIndirectCommand: x, y, z groups).
struct RadixSortParams {
  uvec4 counts;          // x: key count, y: unused, z: block count, w: histogram entries
  uvec4 block_dispatch;  // xyz: one workgroup per block (histogram, scatter)
  uvec4 scan_dispatch;   // xyz: one workgroup per SCAN_BLOCK histogram entries (reduce, downsweep)
};

struct RadixSetupPush {
  uvec4 params;  // x: index of the count in PRISMOID_SORT_BINDING_COUNT, y: most keys to sort (the capacity)
};

struct SortKeysPush {
  vec4 eye;      // xyz: the eye in the mesh's local frame
  uvec4 counts;  // x: tetrahedron count
};

PRISMOID_SHARED_END

#if PRISMOID_SORT_WORKGROUP_SIZE != PRISMOID_SORT_RADIX
#error "the histogram and scatter kernels give each invocation one digit"
#endif
#if PRISMOID_SORT_RADIX_BITS * PRISMOID_SORT_PASSES != 32 || PRISMOID_SORT_PASSES % 2 != 0
#error "the passes must cover 32-bit keys and be even in number (the result ends in the caller's buffers)"
#endif

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::RadixSortPush) == 16);
static_assert(sizeof(prismoid::gpu::RadixSortParams) == 48);
static_assert(offsetof(prismoid::gpu::RadixSortParams, block_dispatch) == 16);
static_assert(offsetof(prismoid::gpu::RadixSortParams, scan_dispatch) == 32);
static_assert(sizeof(prismoid::gpu::RadixSetupPush) == 16);
static_assert(sizeof(prismoid::gpu::SortKeysPush) == 32);
static_assert(offsetof(prismoid::gpu::SortKeysPush, counts) == 16);
static_assert(PRISMOID_SORT_RADIX == (1 << PRISMOID_SORT_RADIX_BITS));
#endif

#endif
