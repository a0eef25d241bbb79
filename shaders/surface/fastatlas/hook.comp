#version 460
// Charts, second step (ECL-CC's hooking, specialised to triangles as the paper does): each
// visible triangle joins its visible edge neighbours and the first visible triangle at each of
// its vertices (fa_unite: lock-free, the root is always the lowest triangle).
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

void main() {
  uint t = gl_GlobalInvocationID.x;
  if (t >= fa_push.image.w || fa_parent[t] == PRISMOID_FA_NONE) return;
  FaTriangleGpu tri = fa_triangles[t];
  for (uint k = 0u; k < 3u; ++k) {
    uint n = tri.neighbours[k];
    if (n != PRISMOID_FA_NONE && n < t && fa_parent[n] != PRISMOID_FA_NONE) fa_unite(t, n);
    uint f = fa_vertex_first[tri.vertices[k]];
    if (f < t) fa_unite(t, f);
  }
}
