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

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= fa_push.image.w || fa_parent[t] == PRISMOID_FA_NONE) return;
  uint root = fa_find(t);
  fa_parent[t] = root;
  atomicAdd(fa_state.counts.x, 1u);
  // The atlas draws only the visible triangles (in the order they arrive: its result does not
  // depend on it, atlas.frag).
  fa_visible[atomicAdd(fa_state.draw.x, 3u) / 3u] = t;
  float near = uintBitsToFloat(fa_push.pass.z);
  vec3 v[3];
  for (uint k = 0u; k < 3u; ++k) v[k] = (frame.view * vec4(triangle_corner(t, k), 1.0)).xyz;
  vec3 kept[4];
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    vec3 p = v[i], q = v[(i + 1) % 3];
    float dp = -p.z - near, dq = -q.z - near;  // >= 0: beyond the near plane
    if (dp >= 0.0) kept[n++] = p;
    if ((dp >= 0.0) != (dq >= 0.0)) kept[n++] = p + (q - p) * (dp / (dp - dq));
  }
  if (n == 0) return;
  vec2 lo = vec2(1.0), hi = vec2(-1.0);  // normalized device coordinates, y up
  for (int i = 0; i < n; ++i) {
    float depth = max(-kept[i].z, near);
    vec2 ndc = vec2(kept[i].x / (depth * frame.camera_right.w), kept[i].y / (depth * frame.camera_up.w));
    lo = min(lo, ndc);
    hi = max(hi, ndc);
  }
  lo = max(lo, vec2(-1.0));
  hi = min(hi, vec2(1.0));
  if (!(hi.x > lo.x && hi.y > lo.y)) return;
  vec2 size = vec2(fa_push.image.xy);
  // To whole pixels, y down from the top.
  ivec2 p0 = ivec2(floor(vec2((lo.x + 1.0) * 0.5 * size.x, (1.0 - hi.y) * 0.5 * size.y)));
  ivec2 p1 = ivec2(ceil(vec2((hi.x + 1.0) * 0.5 * size.x, (1.0 - lo.y) * 0.5 * size.y)));
  atomicMin(fa_boxes[root].x, p0.x);
  atomicMin(fa_boxes[root].y, p0.y);
  atomicMin(fa_boxes[root].z, -p1.x);
  atomicMin(fa_boxes[root].w, -p1.y);
}
