// Layouts shared by the FastAtlas backend's shaders (shaders/surface/fastatlas/) and
// renderer/surface/fastatlas/fastatlas_pass.hpp. The rules the shaders follow are the CPU
// twins' in renderer/surface/fastatlas/ (charts, atlas_packing, atlas_map, atlas_filter).
#ifndef PRISMOID_SHARED_FASTATLAS_H
#define PRISMOID_SHARED_FASTATLAS_H
#include "common.h"

PRISMOID_SHARED_BEGIN

#define PRISMOID_FA_NONE 0xffffffffu
// A texel of the triangle-ID atlas that the border pass filled carries this bit beside the
// triangle, so that the border pass reads only what the raster wrote (the result does not
// depend on the order its invocations run in).
#define PRISMOID_FA_BORDER_BIT 0x80000000u
// A texel the seed pass gave to a triangle the raster left without one (seeds.comp) carries this
// bit: it sorts after every rasterized triangle and before every border under atomicMin.
#define PRISMOID_FA_SEED_BIT 0x40000000u
#define PRISMOID_FA_TRIANGLE_MASK 0x3fffffffu
// A visible triangle (fa_visible) whose texels the chunk pass covers (raster_chunks.comp).
#define PRISMOID_FA_LISTED_BIT 0x80000000u
// The compute raster of the ID atlas (fa_raster.glsl): a triangle whose texel box holds at most
// PRISMOID_FA_RASTER_INLINE texels is covered by one invocation; a larger one in chunks of
// PRISMOID_FA_CHUNK x PRISMOID_FA_CHUNK texels, a workgroup each.
// The depth of a texel claim.comp gave to the visibility pass's triangle: above every depth.
#define PRISMOID_FA_CLAIMED 0xffffffffu
#define PRISMOID_FA_RASTER_INLINE 64u
#define PRISMOID_FA_CHUNK 32u
// Candidate scales are multiples of 2^-16 (PRISMOID_FA_SCALE_ONE = 1), so the GPU's and the CPU
// twin's rounded box sizes agree exactly: ceil(side * num / 2^16) in integers.
#define PRISMOID_FA_SCALE_ONE 65536u
#define PRISMOID_FA_MAX_CANDIDATES 64u
// Border texels are shaded on their triangle's plane outside it (extrapolated) at scales of at
// least this many texels per pixel; below, a texel spans more than two pixels and its shading
// point is held to the triangle (fa_shade.glsl).
#define PRISMOID_FA_EXTRAPOLATE_SCALE 0.5
#define PRISMOID_FA_WORKGROUP 256u
// Sort key of a chart: 0xffff minus its turned height (taller first), over charts already in
// root order (the first, stable sort).
#define PRISMOID_FA_KEY_TOP 0xffffu

// Descriptor bindings of set 0, from PRISMOID_SURFACE_BINDING_BACKEND on.
#define PRISMOID_FA_BINDING_TRIANGLES 16    // FaTriangleGpu[] per global triangle (read only, built at load)
#define PRISMOID_FA_BINDING_PARENT 17       // uint[] per triangle: NONE (not visible) or its union-find parent
#define PRISMOID_FA_BINDING_VERTEX_FIRST 18 // uint[] per welded vertex: the lowest visible triangle there (NONE)
#define PRISMOID_FA_BINDING_BOXES 19        // ivec4[] per triangle (used at roots): x0, y0, -x1, -y1 pixels, all min-reduced
#define PRISMOID_FA_BINDING_KEYS 20         // uint[]: sort keys of the chart list
#define PRISMOID_FA_BINDING_CHARTS 21       // uint[]: the chart list (roots), sorted into packing order
#define PRISMOID_FA_BINDING_PLACED 22       // uvec4[] per triangle (used at roots): atlas x, y, width | turned << 31, height
#define PRISMOID_FA_BINDING_CANDIDATES 23   // uvec4[MAX_CANDIDATES]: fits, height used, widest, 0
#define PRISMOID_FA_BINDING_FRONT 24        // uint[(MAX_CANDIDATES + 1) * atlas width]: push-up front lines
#define PRISMOID_FA_BINDING_STATE 25        // FaStateGpu
#define PRISMOID_FA_BINDING_VISIBILITY 26   // uvec4[] per pixel: triangle + 1 (0: sky), 0, b1, b2 bits
#define PRISMOID_FA_BINDING_ID_ATLAS 27     // r32ui storage image: triangle per texel (NONE: empty; BORDER_BIT: border)
#define PRISMOID_FA_BINDING_COLOR_ATLAS 28  // rgba32f storage image: shaded radiance per texel
#define PRISMOID_FA_BINDING_SCALES 29       // uint[MAX_CANDIDATES]: candidate scales * 2^16, largest first
#define PRISMOID_FA_BINDING_DEPTH_ATLAS 30  // r32ui storage image: the nearest depth per texel (reversed z, float bits; 0: none; CLAIMED)
#define PRISMOID_FA_BINDING_HISTORY 31      // uvec4: x: atlas rows the last frame used (persists: this frame clears up to the larger)
#define PRISMOID_FA_BINDING_VISIBLE 32      // uint[]: this frame's visible triangles, in whatever order (the atlas raster's work; LISTED_BIT: in chunks)
// Temporal reuse (FastAtlas, appendix D): the last frame's atlas and maps, copied at this frame's start.
#define PRISMOID_FA_BINDING_PREV_COLOR 33   // rgba32f storage image: the last frame's colour atlas (rows it used)
#define PRISMOID_FA_BINDING_PREV_PARENT 34  // uint[] per triangle: the last frame's roots
#define PRISMOID_FA_BINDING_PREV_BOXES 35   // ivec4[] per triangle: the last frame's chart boxes
#define PRISMOID_FA_BINDING_PREV_PLACED 36  // uvec4[] per triangle: the last frame's places
#define PRISMOID_FA_BINDING_PREV_STATE 37   // FaStateGpu: the last frame's (its chosen candidate)
#define PRISMOID_FA_BINDING_PREV_FRAME 38   // uniform SurfaceFrame: the last frame's camera
#define PRISMOID_FA_BINDING_RASTER_CHUNKS 39 // uvec2[FaPush::pass.w]: large triangles' chunks (triangle, chunk x | y << 16; NONE: empty)

#define PRISMOID_FA_FLAG_SHADOWS 1u
#define PRISMOID_FA_FLAG_REUSE 2u   // keep last frame's shading: the shading pass launches nothing
#define PRISMOID_FA_FLAG_TEMPORAL 4u  // take a texel's shading from the last atlas where its surface point had it there

// Per triangle, built once at load from the halfedge meshes (vertices welded by position).
struct FaTriangleGpu {
  uvec4 neighbours;  // xyz: the triangle across edge k (NONE on a boundary); w: bit k set when
                     // that neighbour's normal turns by less than the hard-edge threshold
  uvec4 vertices;    // xyz: welded vertex of corner k (global); w: 0
};

struct FaStateGpu {
  uvec4 charts;    // x: charts this frame, y: chosen candidate (MAX_CANDIDATES: none fits), z: 1 when one fits, w: atlas rows used
  uvec4 trace;     // xyz: VkTraceRaysIndirectCommandKHR of the shading pass (atlas width, rows used, 1); w: texels shaded
  uvec4 dispatch;  // xyz: VkDispatchIndirectCommand of the border pass; w: border texels filled
  uvec4 counts;    // x: visible triangles, y: lookup pixels without a usable texel (holes), z: texels holding a triangle, w: 0
  uvec4 clear;     // xyz: VkDispatchIndirectCommand of the clear pass (rows used now or last frame), w: 0
  uvec4 raster;    // xyz: VkDispatchIndirectCommand of the ID atlas raster over the visible triangles (0 groups: nothing fits); w: chunks listed (may pass the capacity)
  uvec4 copy;      // xyz: VkDispatchIndirectCommand copying the rows the last frame used (temporal reuse); w: texels reused
  uvec4 stretch;   // lookup: x, w: low and high word of the sum over pixels of (Gamma^2 + gamma^2) / 2 in 1/4096 (shaders/surface/stretch.glsl), y: pixels, z: largest Gamma (float bits)
};

struct FaPush {
  uvec4 image;   // x: width, y: height, z: flags (PRISMOID_FA_FLAG_*), w: triangles
  uvec4 atlas;   // x: width (power of two), y: height, z: border texels, w: candidates
  uvec4 pass;    // x: packing dispatch (0: every candidate, 1: place the chosen one), or raster pass (0: depth, 1: IDs);
                 // y: welded vertices, z: the near plane's distance (float bits), w: the raster's chunk capacity
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::FaTriangleGpu) == 32);
static_assert(sizeof(prismoid::gpu::FaStateGpu) == 128);
static_assert(sizeof(prismoid::gpu::FaPush) == 48);
#endif
#endif
