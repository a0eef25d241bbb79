#version 460
// Shade gathering (Hillesland & Yang 2016, 3): per pixel, the triangle, level and barycentric
// weights the queue pass stored, the same four bilinear taps, blended from the result texture
// (by hand, in float: hardware filtering keeps only 8 bits of weight). Taps without a triangle
// weigh 0 and the rest are renormalized; a tap never shaded makes the pixel a counted hole. The
// sky where no surface was seen (alpha 0), as sky.frag computes it.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "texel.glsl"

layout(location = 0) out vec4 out_color;

void main() {
  uvec2 pixel = uvec2(gl_FragCoord.xy);
  uvec4 vis = texel_visibility[pixel.y * texel_push.image.x + pixel.x];
  if (vis.x == 0u) {
    out_color = vec4(pixel_sky(gl_FragCoord.xy), 0.0);
    return;
  }
  uint triangle = vis.x - 1u, level = vis.y;
  vec3 b = vec3(0.0, uintBitsToFloat(vis.z), uintBitsToFloat(vis.w));
  b.x = 1.0 - b.y - b.z;
  TexelTaps taps = texel_taps(triangle, b, level);
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  bool hole = false;
  for (uint k = 0u; k < 4u; ++k) {
    uvec2 t = texel_tap(taps, k, level);
    if (!texel_has_triangle(level, t)) continue;
    vec4 c = texel_result[texel_index(level, t)];
    if (c.a == 0.0) hole = true;
    sum += taps.weight[k] * c.rgb;
    weight += taps.weight[k];
  }
  if (hole) atomicAdd(texel_state.counts.y, 1u);
  out_color = vec4(weight > 0.0 ? sum / weight : vec3(0.0), 1.0);
}
