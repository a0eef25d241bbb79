#version 460
// The chart list: every root appends itself (in whatever order the invocations run; the stable
// sorts that follow put the list in root order, then by height). A chart whose triangles all
// lie outside the viewport (it only touches its edge) gets a one-pixel box, as the CPU twin's.
// Its key for the first sort is its root.
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= fa_push.image.w || fa_parent[t] != t) return;
  ivec4 b = fa_boxes[t];
  if (!(-b.z > b.x && -b.w > b.y)) fa_boxes[t] = ivec4(0, 0, -1, -1);
  uint slot = atomicAdd(fa_state.charts.x, 1u);
  fa_keys[slot] = t;
  fa_charts[slot] = t;
}
