// The texel shading backend's buffers and lookup (Hillesland & Yang 2016), shared by the shade
// queue (queue.frag), the shading pass (shade.rgen) and the gather (gather.frag). The rules are
// renderer/surface/texel/texel_atlas.hpp's; reference::texel_lookup is the double-precision twin.
#ifndef PRISMOID_TEXEL_GLSL
#define PRISMOID_TEXEL_GLSL

#include "../../shared/texel.h"

layout(std430, set = 0, binding = PRISMOID_TEXEL_BINDING_TRIANGLES) readonly buffer TexelTriangleBuffer { TexelTriangleGpu texel_triangles[]; };
layout(std430, set = 0, binding = PRISMOID_TEXEL_BINDING_TRIANGLE_INDEX) readonly buffer TexelIndexBuffer { uint texel_triangle_index[]; };
layout(std430, set = 0, binding = PRISMOID_TEXEL_BINDING_CACHE) buffer TexelCacheBuffer { uint texel_cache[]; };
layout(std430, set = 0, binding = PRISMOID_TEXEL_BINDING_TASKS) buffer TexelTaskBuffer { uint texel_tasks[]; };
layout(std430, set = 0, binding = PRISMOID_TEXEL_BINDING_RESULT) buffer TexelResultBuffer { vec4 texel_result[]; };
layout(std430, set = 0, binding = PRISMOID_TEXEL_BINDING_STATE) buffer TexelStateBuffer { TexelStateGpu texel_state; };
layout(std430, set = 0, binding = PRISMOID_TEXEL_BINDING_VISIBILITY) buffer TexelVisibilityBuffer { uvec4 texel_visibility[]; };

layout(push_constant) uniform TexelPushBlock { TexelPush texel_push; };

uint texel_level_width(uint level) { return texel_push.atlas.x >> level; }
uint texel_level_tiles_x(uint level) { return (texel_push.atlas.x >> level) / PRISMOID_TEXEL_TILE; }
uint texel_offset(uint level) { return level < 4u ? texel_push.texel_offset0[level] : texel_push.texel_offset1[level - 4u]; }
uint tile_offset(uint level) { return level < 4u ? texel_push.tile_offset0[level] : texel_push.tile_offset1[level - 4u]; }
uint texel_index(uint level, uvec2 t) { return texel_offset(level) + t.y * texel_level_width(level) + t.x; }
uint tile_index(uint level, uvec2 t) { return tile_offset(level) + (t.y / PRISMOID_TEXEL_TILE) * texel_level_tiles_x(level) + t.x / PRISMOID_TEXEL_TILE; }

// Atlas coordinates of a point relative to its triangle's chart origin (level-0 texel units).
vec2 texel_relative_uv(uint triangle, vec3 bary) {
  TexelTriangleGpu t = texel_triangles[triangle];
  return bary.x * t.uv01.xy + bary.y * t.uv01.zw + bary.z * t.uv2.xy;
}

// floor(log2(footprint) + bias) in [0, levels - 1]; footprint = the longer of the atlas-coordinate
// changes one pixel right (dx) and one pixel down (dy), as barycentric differences.
uint texel_select_level(uint triangle, vec3 dbx, vec3 dby) {
  TexelTriangleGpu t = texel_triangles[triangle];
  vec2 ux = dbx.x * t.uv01.xy + dbx.y * t.uv01.zw + dbx.z * t.uv2.xy;
  vec2 uy = dby.x * t.uv01.xy + dby.y * t.uv01.zw + dby.z * t.uv2.xy;
  float footprint = max(length(ux), length(uy));
  if (!(footprint > 0.0) || isinf(footprint)) return 0u;
  float l = floor(log2(footprint) + texel_push.lod.x);
  return uint(clamp(l, 0.0, float(texel_push.atlas.z - 1u)));
}

// The four bilinear taps of the point at `level`: texel (base + (k & 1, k >> 1)) with weight
// w[k]. The chart origin is a multiple of 2^level, so the tap grid is found from the small
// relative coordinates: origin / 2^level + floor(rel / 2^level - 0.5), exactly.
struct TexelTaps {
  ivec2 base;
  vec4 weight;  // (base), (+1, 0), (0, +1), (+1, +1)
};
TexelTaps texel_taps(uint triangle, vec3 bary, uint level) {
  TexelTriangleGpu t = texel_triangles[triangle];
  vec2 f = texel_relative_uv(triangle, bary) / float(1u << level) - 0.5;
  vec2 fl = floor(f);
  vec2 a = f - fl;
  TexelTaps taps;
  taps.base = ivec2(t.origin.xy >> level) + ivec2(fl);
  taps.weight = vec4((1.0 - a.x) * (1.0 - a.y), a.x * (1.0 - a.y), (1.0 - a.x) * a.y, a.x * a.y);
  return taps;
}

// Tap k's texel clamped to the level, and whether it holds a triangle (else its weight is 0).
uvec2 texel_tap(TexelTaps taps, uint k, uint level) {
  ivec2 p = taps.base + ivec2(k & 1u, k >> 1u);
  ivec2 hi = ivec2(int(texel_push.atlas.x >> level) - 1, int(texel_push.atlas.y >> level) - 1);
  return uvec2(clamp(p, ivec2(0), hi));
}
bool texel_has_triangle(uint level, uvec2 t) { return texel_triangle_index[texel_index(level, t)] != PRISMOID_TEXEL_NO_TRIANGLE; }

#endif
