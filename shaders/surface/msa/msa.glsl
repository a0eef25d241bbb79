// The meshlet shading atlas's buffers and block arithmetic (shaders/shared/msa.h), shared by
// its passes; renderer/surface/msa/msa_pass.cpp's msa_* functions are the CPU twins.
#ifndef PRISMOID_MSA_GLSL
#define PRISMOID_MSA_GLSL

#include "../../shared/msa.h"

// Triangles' chart corners and meshlets' extents: written only by frame_charts.comp (per-frame charts).
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_TRIANGLES) buffer MsaTriangleBuffer { MsaTriangleGpu msa_triangles[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_MESHLETS) buffer MsaMeshletBuffer { MsaMeshletGpu msa_meshlets[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_MESHLET_TRIANGLES) readonly buffer MsaMeshletTriangleBuffer { uint msa_meshlet_triangles[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_BLOCKS) buffer MsaBlockBuffer { MsaBlockGpu msa_blocks[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_DENSITY) buffer MsaDensityBuffer { uint msa_density[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_CLASSES) buffer MsaClassBuffer { MsaClassGpu msa_classes[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_CLASS_SUPERBLOCKS) buffer MsaClassSuperblockBuffer { uint msa_class_superblocks[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_FREE_SLOTS) buffer MsaFreeSlotBuffer { uint msa_free_slots[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_POOL) buffer MsaPoolBuffer { uint msa_pool[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_STATE) buffer MsaStateBuffer { MsaStateGpu msa_state; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_TASKS) buffer MsaTaskBuffer { uint msa_tasks[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_RESULT) buffer MsaResultBuffer { vec4 msa_result[]; };
layout(std430, set = 0, binding = PRISMOID_MSA_BINDING_VISIBILITY) buffer MsaVisibilityBuffer { uvec4 msa_visibility[]; };

layout(push_constant) uniform MsaPushBlock { MsaPush msa_push; };

uvec2 msa_class_size(uint c) { return uvec2(PRISMOID_MSA_MIN_BLOCK << (c / PRISMOID_MSA_SIZES), PRISMOID_MSA_MIN_BLOCK << (c % PRISMOID_MSA_SIZES)); }

// The smallest power of two >= n in [8, 512], as a level 0 .. 6.
uint msa_size_level(float n) {
  uint level = 0u;
  while (level + 1u < PRISMOID_MSA_SIZES && float(PRISMOID_MSA_MIN_BLOCK << level) < n) ++level;
  return level;
}

// The class of a meshlet with chart `extent` wanting `density` texels per unit: its rectangle
// scaled plus a texel of border per side, each side rounded up to a power of two.
uint msa_class_for(vec2 extent, float density) {
  return msa_size_level(ceil(extent.x * density) + 2.0) * PRISMOID_MSA_SIZES + msa_size_level(ceil(extent.y * density) + 2.0);
}

// Texels per chart unit of a block of class c: the chart fills it less a texel per side.
float msa_block_scale(vec2 extent, uint c) {
  vec2 size = vec2(msa_class_size(c));
  float sx = extent.x > 0.0 ? (size.x - 2.0) / extent.x : 1e30;
  float sy = extent.y > 0.0 ? (size.y - 2.0) / extent.y : 1e30;
  float s = min(sx, sy);
  return s < 1e30 ? s : 1.0;  // a point-like chart (degenerate meshlet): any scale
}

// Origin of slot `slot` of class c.
uvec2 msa_slot_origin(uint c, uint slot) {
  uvec2 size = msa_class_size(c);
  uint per_row = PRISMOID_MSA_SUPERBLOCK / size.x;
  uint per_superblock = per_row * (PRISMOID_MSA_SUPERBLOCK / size.y);
  uint sb = msa_class_superblocks[c * msa_push.limits.x + slot / per_superblock];
  uint local = slot % per_superblock;
  uvec2 sb_origin = uvec2(sb % msa_push.atlas.y, sb / msa_push.atlas.y) * PRISMOID_MSA_SUPERBLOCK;
  return sb_origin + uvec2((local % per_row) * size.x, (local / per_row) * size.y);
}

uint msa_slots_per_superblock(uint c) {
  uvec2 size = msa_class_size(c);
  return (PRISMOID_MSA_SUPERBLOCK / size.x) * (PRISMOID_MSA_SUPERBLOCK / size.y);
}

#ifdef PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../pixel_ray.glsl"

// Whether the triangle's meshlet has a perspective chart this frame (frame_charts.comp).
bool msa_perspective(uint triangle) { return msa_meshlets[msa_triangles[triangle].info.x].info.z == 1u; }

// The triangle's corners' distances along the view (camera-space depth).
vec3 msa_corner_depths(uint triangle) {
  vec3 z;
  for (uint k = 0u; k < 3u; ++k) z[k] = -(frame.view * vec4(triangle_corner(triangle, k), 1.0)).z;
  return z;
}

// A perspective chart is affine in the image, not on the surface: the weights of a surface point
// in the image are its barycentric weights times its corners' depths, renormalized, and back.
vec3 msa_image_weights(vec3 bary, vec3 z) {
  vec3 w = bary * z;
  return w / (w.x + w.y + w.z);
}
vec3 msa_surface_weights(vec3 w, vec3 z) {
  vec3 b = w / z;
  return b / (b.x + b.y + b.z);
}

// The chart point of the surface point with barycentric weights `bary`.
vec2 msa_chart_point(uint triangle, vec3 bary) {
  MsaTriangleGpu t = msa_triangles[triangle];
  if (msa_perspective(triangle)) bary = msa_image_weights(bary, msa_corner_depths(triangle));
  return bary.x * t.c01.xy + bary.y * t.c01.zw + bary.z * t.c2.xy;
}
#endif

uint msa_texel_index(uvec2 t) { return t.y * msa_push.atlas.x + t.x; }

#endif
