#version 460
// The triangle-ID atlas, first: texels whose centres are pixel centres (at scale 1 every texel is
// one) take the triangle the visibility pass found at that pixel, so that the atlas agrees with
// the visibility buffer wherever both sample, as when both come from one rasterizer; the compute
// raster's exact edge functions do not reproduce the rasterizer's fixed-point snapping, and the
// lookup's hard-edge filter counts a tap only for the pixel's own triangle or an edge neighbour,
// so a pixel-sized triangle's texel given to another neighbour would cost its pixel a tap (9 %
// FLIP on the 1.2 M-triangle scene at 4K on the GPU machine). A claimed texel's depth is
// PRISMOID_FA_CLAIMED, above every depth: the raster's atomicMax leaves it, and no triangle's
// depth equals it in the ID pass. One pixel per invocation; no two pixels map to one texel
// centre, so plain stores suffice.
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform writeonly uimage2D fa_id_atlas;
layout(set = 0, binding = PRISMOID_FA_BINDING_DEPTH_ATLAS, r32ui) uniform writeonly uimage2D fa_depth_atlas;

void main() {
  uvec2 pixel = gl_GlobalInvocationID.xy;
  if (pixel.x >= fa_push.image.x || pixel.y >= fa_push.image.y || fa_state.charts.z == 0u) return;
  uint v = fa_visibility[pixel.y * fa_push.image.x + pixel.x].x;
  if (v == 0u) return;
  uint t = v - 1u;
  FaChartMap m = fa_chart_map(fa_parent[t]);
  vec2 centre = vec2(pixel) + 0.5;
  vec2 texel = floor(fa_to_atlas(m, centre));
  // Only where the raster would test this very point: the texel centre mapped back (the raster's
  // own arithmetic) is the pixel centre.
  if (fa_to_screen(m, texel + 0.5) != centre) return;
  uvec4 p = fa_placed[fa_parent[t]];
  ivec2 lo = ivec2(p.xy), hi = ivec2(p.xy + uvec2(p.z & 0x7fffffffu, p.w));
  if (any(lessThan(ivec2(texel), lo)) || any(greaterThanEqual(ivec2(texel), hi))) return;
  imageStore(fa_depth_atlas, ivec2(texel), uvec4(PRISMOID_FA_CLAIMED));
  imageStore(fa_id_atlas, ivec2(texel), uvec4(t));
}
