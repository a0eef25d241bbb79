// Layouts shared by the compute interval backend (shaders/volume/compute/) and
// renderer/volume/compute_intervals.cpp. Its kernels use descriptor set 0 with the interval
// pass's own bindings (volume.h: frame uniforms, mesh, transfer function, table, grid) plus
// the ones below, so the GLSL both backends include reads the same names at the same places.
#ifndef PRISMOID_SHARED_COMPUTE_INTERVALS_H
#define PRISMOID_SHARED_COMPUTE_INTERVALS_H
#include "common.h"

PRISMOID_SHARED_BEGIN

// Pixels per tile side: one 8x8 workgroup per tile, one invocation per pixel.
#define PRISMOID_CI_TILE 8
#define PRISMOID_CI_TILE_PIXELS 64
// Cells a raster workgroup sets up together in shared memory, one per invocation.
#define PRISMOID_CI_BATCH PRISMOID_CI_TILE_PIXELS
// Intervals a pixel holds back to composite in their own depth order (the k-buffer).
#define PRISMOID_CI_KBUFFER 8
// Invocations per workgroup of the per-cell and per-pair kernels.
#define PRISMOID_CI_WORKGROUP 256
// A cell whose bounds span more tiles than this is binned by a workgroup of its own
// (big_emit.comp), one tile per invocation, rather than by one invocation looping over them:
// cells the near plane cuts, or seen from close by, can span the whole screen, and one such
// invocation held up the whole pass (38 ms of 41 in the armadillo seen from inside, H200).
#define PRISMOID_CI_BIG_CELL_TILES 64
// A tile's pairs are rastered in chunks of at most this many by separate workgroups, each
// writing its pixels' partial result; a merge combines them in chunk order (deterministic).
// Without it, one workgroup walked a tile's whole list (962k pairs in the 8x8 image's one
// tile: 305 ms on the H200). Colour splits only longer lists: where a pixel's order crosses a
// chunk boundary the tile is rastered again whole, which cost more than the split saved on
// the armadillo at 4K (H200: colour 12.9 ms with chunks of 512, 10.3 with 4096).
#define PRISMOID_CI_CHUNK 512
#define PRISMOID_CI_CHUNK_COLOR 4096

#define PRISMOID_CI_BINDING_BINS 14         // uvec4 per cell: pixel columns x0 | x1 << 16, rows y0 | y1 << 16 (cell_bounds.glsl), depth key, pairs
#define PRISMOID_CI_BINDING_OFFSETS 15      // uint per cell: its pair count, then (scanned) its first pair
#define PRISMOID_CI_BINDING_KEYS 16         // uint per pair: tile << depth bits | depth key
#define PRISMOID_CI_BINDING_VALUES 17       // uint per pair: the cell
#define PRISMOID_CI_BINDING_TILE_RANGES 18  // uvec2 per tile: its first pair and one past its last, in sorted order
#define PRISMOID_CI_BINDING_STATS 19        // uint[PRISMOID_CI_STAT_COUNT]
#define PRISMOID_CI_BINDING_OPTICAL_DEPTH 20  // r32f storage image (VolumeTargets::optical_depth)
#define PRISMOID_CI_BINDING_EMISSION 21       // rgba32f storage image (VolumeTargets::emission)
#define PRISMOID_CI_BINDING_BIG_CELLS 22      // uint per big cell: the cell (in no fixed order)
#define PRISMOID_CI_BINDING_CHUNK_BASE 23     // uint per tile: its first chunk's slot, or PRISMOID_CI_UNSPLIT
#define PRISMOID_CI_BINDING_CHUNK_WORK 24     // uvec2 per chunk after a tile's first: the tile, the chunk's index in it
#define PRISMOID_CI_BINDING_SPLIT_TILES 25    // uint per split tile: the tile
#define PRISMOID_CI_BINDING_PARTIALS 26       // ChunkPartial per chunk slot and pixel of the tile (64 per slot)
#define PRISMOID_CI_BINDING_DEPTH_LIMIT PRISMOID_BINDING_DEPTH_LIMIT  // (volume.h), read when push.options.w is 1
#define PRISMOID_CI_UNSPLIT 0xFFFFFFFFu

// What a frame counts (PRISMOID_CI_BINDING_STATS), read back after it.
#define PRISMOID_CI_STAT_PAIRS 0    // (cell, tile) pairs the cells asked for
#define PRISMOID_CI_STAT_SORTED 1   // pairs written and sorted: at most the capacity
#define PRISMOID_CI_STAT_INEXACT 2  // pixels where an interval arrived nearer than one already composited
#define PRISMOID_CI_STAT_BIG_CELLS 3    // cells binned by big_emit.comp
#define PRISMOID_CI_STAT_CHUNK_SLOTS 4  // chunk slots the split tiles took
#define PRISMOID_CI_STAT_EXTRA_CHUNKS 5 // chunks after the first of each split tile
#define PRISMOID_CI_STAT_SPLIT_TILES 6  // tiles rastered in more than one chunk
#define PRISMOID_CI_STAT_REDO_TILES 7   // split tiles rastered again whole (colour out of order across chunks)
// Indirect dispatches (VkDispatchIndirectCommand: x, y, z) sized on the GPU.
#define PRISMOID_CI_ARGS_BIG_EMIT 8
#define PRISMOID_CI_ARGS_CHUNKS 12
#define PRISMOID_CI_ARGS_MERGE 16
#define PRISMOID_CI_STAT_COUNT 20
// The most workgroups an indirect dispatch asks for along x (the minimum every device takes);
// its kernels loop over the rest.
#define PRISMOID_CI_MAX_GROUPS 65535u

// What the tile raster integrates per interval and how it combines them: one variant of it
// each (tile_raster_*.comp).
#define PRISMOID_CI_OPTICAL_DEPTH 0u  // sigma * length of the cell's linear field, summed
#define PRISMOID_CI_EMISSION 1u       // the segment's emission-absorption, composited in depth order
#define PRISMOID_CI_MARCH_DEPTH 2u    // marched optical depth, summed
#define PRISMOID_CI_MARCH_COLOR 3u    // marched colour, composited in depth order
#define PRISMOID_CI_ISOSURFACE 4u     // the nearest isosurface hit

struct ComputeIntervalsPush {
  uvec4 tiles;     // x, y: tiles per row and per column; z: depth bits of a pair key (the tile above them); w: pair capacity
  vec4 depth;      // x: the depth (minus the mesh origin's) that key 0 stands for, y: keys per unit of depth
  vec4 tie_break;  // xyz: the reference's tie-break direction (tet_ray.cpp) in camera orientation
  uvec4 options;   // x: PRISMOID_CI_* (each tile raster variant has its own fixed), y: image width, z: image height, w: 1 when rays end at PRISMOID_CI_BINDING_DEPTH_LIMIT
  uvec4 chunks;    // x: chunk slots (PRISMOID_CI_BINDING_PARTIALS holds x * 64), y: the raster's launch (PRISMOID_CI_LAUNCH_*), z: pairs per chunk
};

// What one chunk leaves for one pixel of a split tile. value: the optical depth (x), the
// composited colour and opacity (premultiplied), or the isosurface hit (shade, distance).
// keys: x, y: the least and greatest key (entry depth) it composited, +inf and -inf if none;
// z: 1 where the chunk composited some interval out of order; x also the hit's depth (isosurface).
struct ChunkPartial {
  vec4 value;
  vec4 keys;
};

// How a tile-raster dispatch finds its work.
#define PRISMOID_CI_LAUNCH_TILES 0u   // one workgroup per tile (x, y): the tile's whole list or its first chunk
#define PRISMOID_CI_LAUNCH_CHUNKS 1u  // workgroups over PRISMOID_CI_BINDING_CHUNK_WORK: the split tiles' other chunks
#define PRISMOID_CI_LAUNCH_REDO 2u    // workgroups over the split tiles the merge marked: each tile's whole list
// The merge marks a split tile (in PRISMOID_CI_BINDING_SPLIT_TILES) whose colour it could not
// put in each pixel's order: it is rastered again whole, by one workgroup.
#define PRISMOID_CI_REDO_BIT 0x80000000u

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::ComputeIntervalsPush) == 80);
static_assert(sizeof(prismoid::gpu::ChunkPartial) == 32);
#endif

#endif
