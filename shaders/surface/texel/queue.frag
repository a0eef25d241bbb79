#version 460
// Shade queueing (Hillesland & Yang 2016, 3), after the depth pre-pass with an EQUAL test: once
// per visible pixel. The pixel's ray meets its triangle's plane at the barycentric weights the
// gather will read at; the level comes from the atlas-coordinate change one pixel right and one
// pixel down (texel_select_level: the paper's per-fragment mip selection, rounded to the finer
// level); each bilinear tap's 8 x 8 tile is checked against the cache of frame stamps and, when
// it was not shaded within the age threshold, claimed (one compare-and-swap wins per tile and
// frame) and appended to the task list. (triangle + 1, level, weights) go to the visibility
// buffer for the gather.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "texel.glsl"

layout(early_fragment_tests) in;

void queue_tile(uint tile) {
  uint now = texel_push.image.w;
  uint stamp = texel_cache[tile];
  if (stamp != 0u && now - stamp < texel_push.atlas.w) return;  // queued this frame, or shaded recently enough
  if (atomicCompSwap(texel_cache[tile], stamp, now) != stamp) return;  // another pixel claimed it this frame
  uint slot = atomicAdd(texel_state.trace.z, 1u);
  texel_tasks[slot] = tile;
}

void main() {
  uint triangle = uint(gl_PrimitiveID);
  uvec2 pixel = uvec2(gl_FragCoord.xy);
  vec3 b, bx, by;
  bool ok = pixel_barycentrics(triangle, gl_FragCoord.xy, b) && pixel_barycentrics(triangle, gl_FragCoord.xy + vec2(1.0, 0.0), bx) &&
            pixel_barycentrics(triangle, gl_FragCoord.xy + vec2(0.0, 1.0), by);
  if (!ok) {
    b = vec3(1.0 / 3.0);
    bx = b;
    by = b;
  }
  vec3 point = clamp_to_triangle(b);
  uint level = texel_select_level(triangle, bx - b, by - b);
  texel_visibility[pixel.y * texel_push.image.x + pixel.x] = uvec4(triangle + 1u, level, floatBitsToUint(point.y), floatBitsToUint(point.z));
  TexelTaps taps = texel_taps(triangle, point, level);
  uint done[4] = uint[4](0xffffffffu, 0xffffffffu, 0xffffffffu, 0xffffffffu);
  for (uint k = 0u; k < 4u; ++k) {
    uvec2 t = texel_tap(taps, k, level);
    if (!texel_has_triangle(level, t)) continue;
    uint tile = tile_index(level, t);
    if (tile == done[0] || tile == done[1] || tile == done[2]) continue;
    done[k] = tile;
    queue_tile(tile);
  }
}
