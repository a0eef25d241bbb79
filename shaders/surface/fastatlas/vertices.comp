#version 460
// Charts, first step (the paper's vertex-uniqueness merge): each welded vertex learns the lowest
// visible triangle that uses it, so that the next step joins every visible triangle at a vertex
// into one chart (a vertex then belongs to one chart, and charts meeting only at a vertex are
// one, as the CPU twin's visible_charts).
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= fa_push.image.w || fa_parent[t] == PRISMOID_FA_NONE) return;
  uvec4 v = fa_triangles[t].vertices;
  for (uint k = 0u; k < 3u; ++k) atomicMin(fa_vertex_first[v[k]], t);
}
