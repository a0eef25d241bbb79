#version 460
// Shadel marking (Li & Guo 3.2), after the depth pre-pass with an EQUAL test: once per visible
// pixel. The pixel's ray (through its sample point, as sky.frag) meets its triangle's plane at
// the barycentric weights the gather will read at; the level of detail comes from the same
// weights one pixel right and one pixel down (exact derivatives of the chart coordinates, no
// helper invocations); every shadel the footprint at that level reads is marked. The pixel's
// triangle + 1, level and weights go to the visibility buffer for the gather.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "htex.glsl"
#include "htex_residency.glsl"
#include "../pixel_ray.glsl"

layout(early_fragment_tests) in;

void main() {
  uint triangle = uint(gl_PrimitiveID);
  uvec2 pixel = uvec2(gl_FragCoord.xy);
  uint index = pixel.y * htex_push.image.x + pixel.x;
  uint face = htex_face_of_triangle[triangle];
  if (face == PRISMOID_HTEX_NONE) {  // a dropped triangle (a point named twice): nothing to read
    htex_visibility[index] = uvec4(triangle + 1u, PRISMOID_HTEX_NONE, 0u, 0u);
    return;
  }
  vec3 b, bx, by;
  bool ok = pixel_barycentrics(triangle, gl_FragCoord.xy, b) && pixel_barycentrics(triangle, gl_FragCoord.xy + vec2(1.0, 0.0), bx) &&
            pixel_barycentrics(triangle, gl_FragCoord.xy + vec2(0.0, 1.0), by);
  if (!ok) {
    b = vec3(1.0 / 3.0);
    bx = b;
    by = b;
  }
  vec3 point = clamp_to_triangle(b);
  uint mesh = triangles[triangle].info.y;
  float lod = htex_level_of_detail(mesh, face, point, bx - b, by - b);
  uint level = htex_pick_level(mesh, lod, htex_push.lod.x, 0u);
  htex_visibility[index] = uvec4(triangle + 1u, level, floatBitsToUint(point.y), floatBitsToUint(point.z));
  htex_mark_footprint(mesh, face, point, level);
}
