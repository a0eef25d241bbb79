#version 460
// The visibility pass (FastAtlas, section 5.1 and appendix A), after the depth pre-pass with an
// EQUAL test: once per pixel whose sample the triangle holds, so a triangle is visible when it
// covers a sample of the framebuffer, the paper's definition. The triangle starts its own set of
// the union-find (the paper sets the component ID in its visibility shader); the pixel's
// triangle and the weights where its ray meets the triangle's plane go to the visibility buffer
// for the lookup.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"

layout(early_fragment_tests) in;

void main() {
  uint triangle = uint(gl_PrimitiveID);
  uvec2 pixel = uvec2(gl_FragCoord.xy);
  vec3 b;
  if (!pixel_barycentrics(triangle, gl_FragCoord.xy, b)) b = vec3(1.0 / 3.0);
  vec3 point = clamp_to_triangle(b);
  fa_visibility[pixel.y * fa_push.image.x + pixel.x] = uvec4(triangle + 1u, 0u, floatBitsToUint(point.y), floatBitsToUint(point.z));
  fa_parent[triangle] = triangle;
}
