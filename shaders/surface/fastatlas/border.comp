#version 460
// Borders for bilinear filtering (FastAtlas, appendix A): every empty texel of a chart's box next
// to one the raster covered takes the triangle there whose plane the texel's ray meets nearest
// (ties: the lower triangle), so that bilinear taps at a chart's edge read shading of its own
// surface. The paper rasterizes a second time with conservative rasterization and a strict depth
// test; lavapipe has no VK_EXT_conservative_rasterization, and this pass gives the same one-texel
// ring on every device. It reads only what the raster and the seed pass wrote (PRISMOID_FA_BORDER_BIT marks what it
// writes), so the result does not depend on the order its invocations run in.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform uimage2D fa_id_atlas;

uint raster_id(ivec2 t) {
  // Rows past those used this frame were not cleared (clear.comp): nothing there.
  if (any(lessThan(t, ivec2(0))) || t.x >= int(fa_push.atlas.x) || t.y >= int(fa_state.charts.w)) return PRISMOID_FA_NONE;
  uint id = imageLoad(fa_id_atlas, t).x;
  return (id & PRISMOID_FA_BORDER_BIT) != 0u ? PRISMOID_FA_NONE : id & PRISMOID_FA_TRIANGLE_MASK;
}

bool in_placed_box(uint root, ivec2 t) {
  uvec4 p = fa_placed[root];
  uvec2 size = uvec2(p.z & 0x7fffffffu, p.w);
  return all(greaterThanEqual(uvec2(t), p.xy)) && all(lessThan(uvec2(t), p.xy + size));
}

void main() {
  ivec2 t = ivec2(gl_GlobalInvocationID.xy);
  if (t.x >= int(fa_push.atlas.x) || t.y >= int(fa_state.charts.w)) return;
  if (imageLoad(fa_id_atlas, t).x != PRISMOID_FA_NONE) return;
  uint best = PRISMOID_FA_NONE;
  float best_distance = 0.0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      uint id = raster_id(t + ivec2(dx, dy));
      if (id == PRISMOID_FA_NONE || id == best) continue;
      uint root = fa_parent[id];
      if (!in_placed_box(root, t)) continue;
      vec2 pixel = fa_to_screen(fa_chart_map(root), vec2(t) + 0.5);
      vec3 b;
      if (!pixel_barycentrics(id, pixel, b)) continue;
      vec3 p = b.x * triangle_corner(id, 0u) + b.y * triangle_corner(id, 1u) + b.z * triangle_corner(id, 2u);
      float distance = length(p - frame.eye.xyz);
      if (best == PRISMOID_FA_NONE || distance < best_distance || (distance == best_distance && id < best)) {
        best = id;
        best_distance = distance;
      }
    }
  if (best == PRISMOID_FA_NONE) return;
  imageStore(fa_id_atlas, t, uvec4(best | PRISMOID_FA_BORDER_BIT));
  atomicAdd(fa_state.dispatch.w, 1u);
}
