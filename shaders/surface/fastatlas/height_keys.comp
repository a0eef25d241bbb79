#version 460
// Keys of the second, stable sort: the chart's turned height (the longer side), tallest first.
// Over a list already in root order, the result is ordered by height and then root, the CPU
// twin's packing_order.
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= fa_state.charts.x) return;
  ivec4 b = fa_boxes[fa_charts[i]];
  uint tall = uint(max(-b.z - b.x, -b.w - b.y));
  fa_keys[i] = PRISMOID_FA_KEY_TOP - min(tall, PRISMOID_FA_KEY_TOP);
}
