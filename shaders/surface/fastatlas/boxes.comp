#version 460
// Charts, last step, and their boxes (FastAtlas, sections 5.1 and 5.2): each visible triangle
// points straight at its root, and its screen box is folded into the root's. The box of a
// triangle is that of its part beyond the near plane (clipped against that one plane: a triangle
// or a quad remains), projected and clamped to the viewport: a triangle crossing the near plane
// gives what the camera sees rather than the huge or folded box of a division by w near 0. The
// CPU twin is fastatlas::triangle_box; boxes are kept in whole pixels (floor, ceil) so that the
// atomics are exact and the result does not depend on their order.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"
#include "fa_triangle.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= fa_push.image.w || fa_parent[t] == PRISMOID_FA_NONE) return;
  uint root = fa_find(t);
  fa_parent[t] = root;
  // The atlas raster covers only the visible triangles (in the order they arrive: its result
  // does not depend on it, fa_raster.glsl).
  fa_visible[atomicAdd(fa_state.counts.x, 1u)] = t;
  vec2 lo, hi;
  if (!fa_screen_box(t, lo, hi)) return;
  // To whole pixels.
  ivec2 p0 = ivec2(floor(lo)), p1 = ivec2(ceil(hi));
  atomicMin(fa_boxes[root].x, p0.x);
  atomicMin(fa_boxes[root].y, p0.y);
  atomicMin(fa_boxes[root].z, -p1.x);
  atomicMin(fa_boxes[root].w, -p1.y);
}
