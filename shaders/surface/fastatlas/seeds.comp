#version 460
// Seeds (the conservative part of the triangle-ID atlas): a visible triangle so small at the chosen
// scale that no texel centre lies inside it got no texel from the raster, and its pixels would find
// none of their own. Each visible triangle claims the texel under the projection of its corners'
// mean, when that texel is empty: under atomicMin every rasterized texel keeps its triangle, and of
// two seeds the lower triangle wins, whatever the order. The border pass then grows seeds as it
// grows rasterized texels. (The paper's conservative rasterization gives such triangles texels;
// lavapipe has none.)
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;
layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform uimage2D fa_id_atlas;

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= fa_push.image.w || fa_state.charts.z == 0u) return;
  uint root = fa_parent[t];
  if (root == PRISMOID_FA_NONE) return;
  vec2 sum = vec2(0.0);
  for (uint k = 0u; k < 3u; ++k) {
    vec4 clip = frame.projection * (frame.view * vec4(triangle_corner(t, k), 1.0));
    if (!(clip.w > 0.0)) return;  // crossing the eye's plane: not a small triangle
    sum += (clip.xy / clip.w + 1.0) * 0.5 * vec2(fa_push.image.xy);
  }
  FaChartMap m = fa_chart_map(root);
  vec2 u = fa_to_atlas(m, sum / 3.0);
  uvec4 p = fa_placed[root];
  ivec2 lo = ivec2(p.xy), hi = ivec2(p.xy + uvec2(p.z & 0x7fffffffu, p.w)) - 1;
  ivec2 texel = clamp(ivec2(floor(u)), lo, hi);
  if (imageLoad(fa_id_atlas, texel).x != PRISMOID_FA_NONE) return;  // taken: most triangles stop here
  imageAtomicMin(fa_id_atlas, texel, t | PRISMOID_FA_SEED_BIT);
}
