#version 460
// Meshlet visibility (Neff et al. 2022, 3: "a visibility buffer at meshlet granularity"), after
// the depth pre-pass with an EQUAL test: once per visible pixel. The pixel's barycentric weights
// go to the visibility buffer for the display pass; its meshlet is marked seen with the density
// it wants: texels per chart unit such that a texel is at most a pixel here (1 / the longer of
// the chart-coordinate changes one pixel right and one pixel down), the maximum over its pixels.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "msa.glsl"

layout(early_fragment_tests) in;

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
  msa_visibility[pixel.y * msa_push.image.x + pixel.x] = uvec4(triangle + 1u, 0u, floatBitsToUint(point.y), floatBitsToUint(point.z));
  MsaTriangleGpu t = msa_triangles[triangle];
  vec2 c = msa_chart_point(triangle, b);
  vec2 cx = msa_chart_point(triangle, bx) - c, cy = msa_chart_point(triangle, by) - c;
  float footprint = max(length(cx), length(cy));
  // A pixel whose footprint cannot be measured (ray parallel to the plane) still marks the
  // meshlet seen, at the least density a float can carry.
  float density = footprint > 0.0 && !isinf(footprint) ? 1.0 / footprint : 1e-30;
  atomicMax(msa_density[t.info.x], floatBitsToUint(max(density, 1e-30)));
}
