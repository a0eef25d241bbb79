#version 460
// The triangle-ID atlas, large triangles: one workgroup per listed chunk of a triangle's texel
// box (raster.comp lists them), each invocation a few of its texels. The workgroups walk the list
// in strides, so the dispatch is fixed and needs no count read back. fa_push.pass.x: 0 depth,
// 1 triangle IDs, as in raster.comp.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"
#include "fa_raster.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

void main() {
  bool id_pass = fa_push.pass.x == 1u;
  uint listed = min(fa_state.raster.w, fa_push.pass.w);
  for (uint c = gl_WorkGroupID.x; c < listed; c += gl_NumWorkGroups.x) {
    uvec2 chunk = fa_chunks[c];
    uint t = chunk.x;
    FaRasterTriangle r;
    if (t == PRISMOID_FA_NONE || !fa_raster_setup(t, r)) continue;
    ivec2 origin = r.lo + ivec2(chunk.y & 0xffffu, chunk.y >> 16) * int(PRISMOID_FA_CHUNK);
    for (uint y = gl_LocalInvocationID.y; y < PRISMOID_FA_CHUNK; y += 16u)
      for (uint x = gl_LocalInvocationID.x; x < PRISMOID_FA_CHUNK; x += 16u) {
        ivec2 texel = origin + ivec2(x, y);
        if (all(lessThanEqual(texel, r.hi))) fa_raster_texel(r, t, texel, id_pass);
      }
  }
}
