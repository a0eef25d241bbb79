#version 460
// The Htex gather (Li & Guo 3.4): per pixel, the triangle, level and barycentric weights the
// marking pass stored, the lookup's footprint (htex_footprint: up to 12 texels with normalized
// weights), each texel through the page table to its pool slot, blended. A texel whose group has
// no page (the pool was full even at the largest bias) is left out and the rest renormalized;
// such pixels are counted (HtexStateGpu::result.y). The sky where no surface was seen (alpha 0),
// as sky.frag computes it.
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "htex.glsl"
#include "htex_residency.glsl"

layout(location = 0) out vec4 out_color;

void main() {
  uvec2 pixel = uvec2(gl_FragCoord.xy);
  uvec4 vis = htex_visibility[pixel.y * htex_push.image.x + pixel.x];
  if (vis.x == 0u) {
    vec2 ndc = (gl_FragCoord.xy + frame.subpixel.xy) * frame.viewport.zw * 2.0 - 1.0;
    vec3 d = normalize(frame.camera_forward.xyz + ndc.x * frame.camera_right.w * frame.camera_right.xyz -
                       ndc.y * frame.camera_up.w * frame.camera_up.xyz);
    float t = 0.5 * (1.0 + dot(d, frame.sky_up.xyz));
    out_color = vec4(frame.sky_bottom.rgb + (frame.sky_top.rgb - frame.sky_bottom.rgb) * t, 0.0);
    return;
  }
  if (vis.y == PRISMOID_HTEX_NONE) {
    out_color = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  uint triangle = vis.x - 1u;
  uint face = htex_face_of_triangle[triangle];
  uint mesh = triangles[triangle].info.y;
  vec3 b = vec3(0.0, uintBitsToFloat(vis.z), uintBitsToFloat(vis.w));
  b.x = 1.0 - b.y - b.z;
  HtexFootprint fp = htex_footprint(mesh, face, b, vis.y);
  bool indirect = (htex_push.image.z & PRISMOID_HTEX_FLAG_INDIRECT) != 0u;
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  bool hole = false;
  for (uint k = 0u; k < fp.count; ++k) {
    uvec2 v = htex_virtual_texel(mesh, fp.texel[k].x, vis.y, fp.texel[k].z, fp.texel[k].w);
    uint page = htex_page_table[htex_group_of(v)];
    if (page == PRISMOID_HTEX_NOT_RESIDENT) {
      hole = true;
      continue;
    }
    uint slot = htex_slot(page, v);
    vec3 c = htex_pool[slot].rgb;
    if (indirect) c += htex_indirect[slot].rgb;
    sum += fp.weight[k] * c;
    weight += fp.weight[k];
  }
  if (hole) atomicAdd(htex_state.result.y, 1u);
  out_color = vec4(weight > 0.0 ? sum / weight : vec3(0.0), 1.0);
}
