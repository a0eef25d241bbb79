#version 460
// Test only (tests/surface/test_htex_gi.cpp): htex_walk_texel at a list of queries, to be held to
// the C++ htex::walk_texel.
#extension GL_GOOGLE_include_directive : require
#include "htex.glsl"
#include "htex_walk.glsl"

layout(local_size_x = 64) in;

struct WalkQuery {
  uvec4 texel;   // x: global edge, y: side n, z: i, w: j
  ivec4 offset;  // xy
};
layout(std430, set = 0, binding = 40) readonly buffer Queries { WalkQuery queries[]; };
layout(std430, set = 0, binding = 41) writeonly buffer Results { ivec4 results[]; };  // x: ok, y: edge, z: i, w: j
layout(push_constant) uniform Push { uint count; };

void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= count) return;
  WalkQuery q = queries[id];
  HtexQuadTexel to;
  bool ok = htex_walk_texel(q.texel.y, HtexQuadTexel(q.texel.x, ivec2(q.texel.zw)), q.offset.xy, to);
  results[id] = ok ? ivec4(1, int(to.edge), to.ij) : ivec4(0);
}
