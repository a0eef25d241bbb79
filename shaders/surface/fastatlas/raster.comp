#version 460
// The triangle-ID atlas, per visible triangle (fa_raster.glsl says how and why in compute). A
// triangle whose texel box is small loops over it in this invocation; a larger one is cut into
// chunks of PRISMOID_FA_CHUNK x PRISMOID_FA_CHUNK texels that raster_chunks.comp covers a
// workgroup each, so that one big triangle does not hold up a whole frame. Two passes
// (fa_push.pass.x): 0 keeps each texel's nearest depth and lists the chunks, 1 writes the
// triangle whose depth that is. A triangle listed in pass 0 carries PRISMOID_FA_LISTED_BIT in
// fa_visible, so pass 1 leaves it to the chunks just as pass 0 did.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"
#include "fa_raster.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= fa_state.counts.x) return;
  bool id_pass = fa_push.pass.x == 1u;
  uint entry = fa_visible[i];
  if (id_pass && (entry & PRISMOID_FA_LISTED_BIT) != 0u) return;  // the chunks' work
  uint t = entry & PRISMOID_FA_TRIANGLE_MASK;
  FaRasterTriangle r;
  if (!fa_raster_setup(t, r)) return;
  ivec2 size = r.hi - r.lo + 1;
  if (!id_pass && size.x * size.y > int(PRISMOID_FA_RASTER_INLINE)) {
    uvec2 chunks = (uvec2(size) + PRISMOID_FA_CHUNK - 1u) / PRISMOID_FA_CHUNK;
    uint n = chunks.x * chunks.y, capacity = fa_push.pass.w;
    uint first = atomicAdd(fa_state.raster.w, n);
    if (first + n <= capacity) {
      for (uint k = 0u; k < n; ++k) fa_chunks[first + k] = uvec2(t, (k % chunks.x) | ((k / chunks.x) << 16));
      fa_visible[i] = entry | PRISMOID_FA_LISTED_BIT;
      return;
    }
    // The list is full (many large triangles over one another): this invocation covers the
    // triangle itself in both passes, slower but the same texels; the slots it reserved below
    // the capacity are marked empty.
    for (uint k = first; k < min(first + n, capacity); ++k) fa_chunks[k] = uvec2(PRISMOID_FA_NONE, 0u);
  }
  for (int y = r.lo.y; y <= r.hi.y; ++y)
    for (int x = r.lo.x; x <= r.hi.x; ++x) fa_raster_texel(r, t, ivec2(x, y), id_pass);
}
