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

#define PRISMOID_CI_BINDING_BINS 14         // uvec4 per cell: tile columns x0 | x1 << 16, rows y0 | y1 << 16, depth key, pairs
#define PRISMOID_CI_BINDING_OFFSETS 15      // uint per cell: its pair count, then (scanned) its first pair
#define PRISMOID_CI_BINDING_KEYS 16         // uint per pair: tile << depth bits | depth key
#define PRISMOID_CI_BINDING_VALUES 17       // uint per pair: the cell
#define PRISMOID_CI_BINDING_TILE_RANGES 18  // uvec2 per tile: its first pair and one past its last, in sorted order
#define PRISMOID_CI_BINDING_STATS 19        // uint[PRISMOID_CI_STAT_COUNT]
#define PRISMOID_CI_BINDING_OPTICAL_DEPTH 20  // r32f storage image (VolumeTargets::optical_depth)
#define PRISMOID_CI_BINDING_EMISSION 21       // rgba32f storage image (VolumeTargets::emission)

// What a frame counts (PRISMOID_CI_BINDING_STATS), read back after it.
#define PRISMOID_CI_STAT_PAIRS 0    // (cell, tile) pairs the cells asked for
#define PRISMOID_CI_STAT_SORTED 1   // pairs written and sorted: at most the capacity
#define PRISMOID_CI_STAT_INEXACT 2  // pixels where an interval arrived nearer than one already composited
#define PRISMOID_CI_STAT_COUNT 4

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
  uvec4 options;   // x: PRISMOID_CI_* (each tile raster variant has its own fixed), y: image width, z: image height, w: unused
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::ComputeIntervalsPush) == 64);
#endif

#endif
