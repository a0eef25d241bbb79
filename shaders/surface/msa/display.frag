#version 460
// The meshlet shading atlas's display pass (Neff et al. 2022, 3): per pixel, the triangle and
// weights of the visibility pass, the point's chart coordinates, through its meshlet's block
// mapping to atlas texels, blended bilinearly by hand in float from the atlas (taps of texels
// outside the meshlet weigh 0, the rest renormalized). A pixel whose meshlet holds no block (the
// atlas ran out) or whose taps are all empty is counted (MsaStateGpu::demand.z) and drawn black.
// The sky where no surface was seen (alpha 0), as sky.frag computes it.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "msa.glsl"
#include "../stretch.glsl"

layout(location = 0) out vec4 out_color;

void main() {
  uvec2 pixel = uvec2(gl_FragCoord.xy);
  uvec4 vis = msa_visibility[pixel.y * msa_push.image.x + pixel.x];
  if (vis.x == 0u) {
    out_color = vec4(pixel_sky(gl_FragCoord.xy), 0.0);
    return;
  }
  uint triangle = vis.x - 1u;
  vec3 bary = vec3(0.0, uintBitsToFloat(vis.z), uintBitsToFloat(vis.w));
  bary.x = 1.0 - bary.y - bary.z;
  uint m = msa_triangles[triangle].info.x;
  MsaBlockGpu b = msa_blocks[m];
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  if (b.block.z != PRISMOID_MSA_NONE) {
    uvec2 size = msa_class_size(b.block.z);
    float s = msa_block_scale(msa_meshlets[m].extent.xy, b.block.z);
    vec2 chart = msa_chart_point(triangle, bary);
    vec2 f = 1.0 + chart * s - 0.5;  // relative to the block's origin
    // The stretch between screen and atlas here: the chart's change one pixel right and down.
    vec3 bx, by;
    float big, small;
    if (pixel_barycentrics(triangle, gl_FragCoord.xy + vec2(1.0, 0.0), bx) && pixel_barycentrics(triangle, gl_FragCoord.xy + vec2(0.0, 1.0), by) &&
        pixel_stretch((msa_chart_point(triangle, bx) - chart) * s, (msa_chart_point(triangle, by) - chart) * s, big, small)) {
      uint term = stretch_sum_term(big, small);
    if (atomicAdd(msa_state.stretch.x, term) > 0xffffffffu - term) atomicAdd(msa_state.stretch.w, 1u);  // the carry
      atomicAdd(msa_state.stretch.y, 1u);
      atomicMax(msa_state.stretch.z, floatBitsToUint(big));
    }
    vec2 fl = floor(f);
    vec2 a = f - fl;
    vec4 w = vec4((1.0 - a.x) * (1.0 - a.y), a.x * (1.0 - a.y), (1.0 - a.x) * a.y, a.x * a.y);
    for (uint k = 0u; k < 4u; ++k) {
      ivec2 t = clamp(ivec2(fl) + ivec2(k & 1u, k >> 1u), ivec2(0), ivec2(size) - 1);
      vec4 c = msa_result[msa_texel_index(b.block.xy + uvec2(t))];
      if (c.a == 0.0) continue;
      sum += w[k] * c.rgb;
      weight += w[k];
    }
  }
  if (!(weight > 0.0)) atomicAdd(msa_state.demand.z, 1u);
  out_color = vec4(weight > 0.0 ? sum / weight : vec3(0.0), 1.0);
}
