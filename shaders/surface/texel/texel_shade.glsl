// The texel shading pass (Hillesland & Yang 2016, 3, "shade evaluation"): one ray-generation
// invocation per texel of each queued 8 x 8 tile, launched as (8, 8, tiles) by
// vkCmdTraceRaysIndirectKHR (a ray-generation shader, not compute, so that shadow rays can be
// traced on the GPU machine, which has no ray queries). The texel's triangle comes from the
// triangle index texture; its centre, mapped back through the triangle's chart map, gives
// barycentric weights (outside the triangle for padding texels: the point lies in the
// triangle's plane); the shared shading code shades that point. Included by shade.rgen (with
// shadow rays) and shade_unshadowed.rgen (every light visible, as reference::direct_light).
#extension GL_GOOGLE_include_directive : require
#ifndef PRISMOID_SURFACE_VERTEX_BUFFERS
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#endif
#include "../surface_point.glsl"
#include "texel.glsl"

void main() {
  uint tile = texel_tasks[gl_LaunchIDEXT.z];
  uint level = 0u;
  while (level + 1u < texel_push.atlas.z && tile >= tile_offset(level + 1u)) ++level;
  uint local = tile - tile_offset(level);
  uint tiles_x = texel_level_tiles_x(level);
  uvec2 t = uvec2((local % tiles_x) * PRISMOID_TEXEL_TILE + gl_LaunchIDEXT.x, (local / tiles_x) * PRISMOID_TEXEL_TILE + gl_LaunchIDEXT.y);
  uint index = texel_index(level, t);
  uint triangle = texel_triangle_index[index];
  if (triangle == PRISMOID_TEXEL_NO_TRIANGLE) return;
  // The centre relative to the chart origin (exact: both are multiples of 2^-1 texels of level 0).
  TexelTriangleGpu tr = texel_triangles[triangle];
  vec2 c = (vec2(t) + 0.5) * float(1u << level) - vec2(tr.origin.xy);
  vec2 d1 = tr.uv01.zw - tr.uv01.xy, d2 = tr.uv2.xy - tr.uv01.xy, q = c - tr.uv01.xy;
  float det = d1.x * d2.y - d1.y * d2.x;
  vec3 bary = vec3(1.0 / 3.0);
  if (det != 0.0) {
    float b1 = (q.x * d2.y - q.y * d2.x) / det, b2 = (d1.x * q.y - d1.y * q.x) / det;
    if (!isnan(b1) && !isinf(b1) && !isnan(b2) && !isinf(b2)) bary = vec3(1.0 - b1 - b2, b1, b2);
  }
  ShadingInput s = shading_input_at(triangle, bary, triangle_point(triangle, bary), frame.eye.xyz);
  texel_result[index] = vec4(shade_surface_point(s.point, s.material, s.emission), 1.0);
  atomicAdd(texel_state.trace.w, 1u);
}
