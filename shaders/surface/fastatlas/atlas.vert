#version 460
// The triangle-ID atlas (FastAtlas, appendix A): every triangle of a chart drawn where the
// packer placed the chart, by its own screen projection scaled and moved (fa_to_atlas), with
// the original frustum's side planes as clip distances so that only what lies on the screen is
// kept; depth is the screen's, so where a chart overlaps itself the nearer surface wins, as on
// the screen (two draws: atlas_depth.frag keeps each texel's nearest depth, atlas.frag the
// triangle there). The map is applied to homogeneous coordinates (a * clip.xy + b * clip.w), so the
// hardware's clipping stays right for triangles that cross w = 0. Vertices are pulled: vertex
// 3 i + k is corner k of the i-th visible triangle (fa_visible; an indirect draw of them alone).
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"

layout(location = 0) flat out uint out_triangle;

// Both draws of the atlas (atlas_depth.frag, atlas.frag) must see the same depth bit for bit.
invariant gl_Position;

out float gl_ClipDistance[4];

void main() {
  uint t = fa_visible[uint(gl_VertexIndex) / 3u], k = uint(gl_VertexIndex) % 3u;
  out_triangle = t;
  uint root = fa_parent[t];
  if (root == PRISMOID_FA_NONE || fa_state.charts.z == 0u) {  // not reached through the indirect draw: kept as a guard
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
    for (int i = 0; i < 4; ++i) gl_ClipDistance[i] = -1.0;
    return;
  }
  vec4 clip = frame.projection * (frame.view * vec4(triangle_corner(t, k), 1.0));
  // Pixels (y down from the top) times w.
  vec2 pixel_w = 0.5 * vec2(fa_push.image.xy) * (clip.xy + clip.w);
  FaChartMap m = fa_chart_map(root);
  vec2 d = (pixel_w - m.screen_origin * clip.w) * m.scale;
  vec2 texel_w = m.atlas_origin * clip.w + (m.turned ? d.yx : d);
  vec2 ndc_w = texel_w * 2.0 / vec2(fa_push.atlas.xy) - clip.w;
  gl_Position = vec4(ndc_w, clip.z, clip.w);
  gl_ClipDistance[0] = clip.w + clip.x;
  gl_ClipDistance[1] = clip.w - clip.x;
  gl_ClipDistance[2] = clip.w + clip.y;
  gl_ClipDistance[3] = clip.w - clip.y;
}
