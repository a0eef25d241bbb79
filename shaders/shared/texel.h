// Layouts shared by the texel shading backend's shaders (shaders/surface/texel/) and
// renderer/surface/texel/texel_pass.hpp. The atlas itself (charts, levels, triangle index texture,
// lookup rules) is renderer/surface/texel/texel_atlas.hpp; its CPU arithmetic is the twin of
// shaders/surface/texel/texel.glsl.
//
// Buffers hold every level one after the other: texel (i, j) of level L is at
// texel_offset[L] + j * (width >> L) + i; tile (ti, tj) (8 x 8 texels) at
// tile_offset[L] + tj * ((width >> L) / 8) + ti.
#ifndef PRISMOID_SHARED_TEXEL_H
#define PRISMOID_SHARED_TEXEL_H
#include "common.h"

PRISMOID_SHARED_BEGIN

#define PRISMOID_TEXEL_NO_TRIANGLE 0xffffffffu
#define PRISMOID_TEXEL_TILE 8u
#define PRISMOID_TEXEL_MAX_LEVELS 8u

// Descriptor bindings of set 0, from PRISMOID_SURFACE_BINDING_BACKEND on.
#define PRISMOID_TEXEL_BINDING_TRIANGLES 16       // TexelTriangleGpu[] per global triangle (read only)
#define PRISMOID_TEXEL_BINDING_TRIANGLE_INDEX 17  // uint[] per texel, all levels: triangle or NO_TRIANGLE (read only)
#define PRISMOID_TEXEL_BINDING_CACHE 18           // uint[] per tile, all levels: frame stamp of its last shading, 0: never (persists)
#define PRISMOID_TEXEL_BINDING_TASKS 19           // uint[]: tiles (index over all levels) to shade this frame
#define PRISMOID_TEXEL_BINDING_RESULT 20          // vec4[] per texel, all levels: shaded radiance, a = 1 once shaded (persists)
#define PRISMOID_TEXEL_BINDING_STATE 21           // TexelStateGpu: counters and the indirect launch
#define PRISMOID_TEXEL_BINDING_VISIBILITY 22      // uvec4[] per pixel: triangle + 1 (0: sky), level, b1, b2 bits

#define PRISMOID_TEXEL_FLAG_SHADOWS 1u

// A triangle's corner atlas coordinates (level-0 texel units) relative to its chart's content
// origin, which is a multiple of 2^(levels - 1): relative coordinates stay small, so float keeps
// them to ~1e-5 texels wherever the chart lies in the atlas.
struct TexelTriangleGpu {
  vec4 uv01;    // corner 0 xy, corner 1 xy
  vec4 uv2;     // corner 2 xy, 0, 0
  uvec4 origin; // x, y: the chart's content origin (level-0 texels); z: chart; w: 0
};

struct TexelStateGpu {
  uvec4 trace;   // xyz: VkTraceRaysIndirectCommandKHR of the shading pass (8, 8, tiles); w: texels shaded (with a triangle)
  uvec4 counts;  // x: 0, y: gather pixels with a tap (holding a triangle) never shaded (holes), zw: 0
};

struct TexelPush {
  uvec4 image;         // x: width, y: height, z: flags (PRISMOID_TEXEL_FLAG_*), w: this frame's stamp (>= 1)
  uvec4 atlas;         // x: level-0 width, y: level-0 height, z: levels, w: cache age threshold (frames, >= 1)
  uvec4 texel_offset0; // levels 0-3
  uvec4 texel_offset1; // levels 4-7
  uvec4 tile_offset0;
  uvec4 tile_offset1;
  vec4 lod;            // x: mip bias added to log2 of the footprint before rounding down
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::TexelTriangleGpu) == 48);
static_assert(sizeof(prismoid::gpu::TexelStateGpu) == 32);
static_assert(sizeof(prismoid::gpu::TexelPush) == 112);
#endif
#endif
