// Shading into the atlas (FastAtlas, appendix A): one ray-generation invocation per texel of the
// rows the packer used, launched as (atlas width, rows, 1) by vkCmdTraceRaysIndirectKHR (ray
// generation, not compute, so that shadow rays can be traced on the GPU machine, which has no ray
// queries). The texel's centre, mapped back through its chart's map to the screen, gives a pixel
// ray; where that ray meets the texel's triangle's plane (outside the triangle for border
// texels) the shared shading code shades, as every backend does. Included by shade.rgen (with
// shadow rays) and shade_unshadowed.rgen (every light visible, as reference::direct_light).
#extension GL_GOOGLE_include_directive : require
#ifndef PRISMOID_SURFACE_VERTEX_BUFFERS
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#endif
#include "../surface_point.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"

layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform readonly uimage2D fa_id_atlas;
layout(set = 0, binding = PRISMOID_FA_BINDING_COLOR_ATLAS, rgba32f) uniform writeonly image2D fa_color_atlas;

void main() {
  ivec2 t = ivec2(gl_LaunchIDEXT.xy);
  uint id = imageLoad(fa_id_atlas, t).x;
  if (id == PRISMOID_FA_NONE) return;
  uint triangle = id & PRISMOID_FA_TRIANGLE_MASK;
  vec2 pixel = fa_to_screen(fa_chart_map(fa_parent[triangle]), vec2(t) + 0.5);
  vec3 bary;
  if (!pixel_barycentrics(triangle, pixel, bary)) bary = vec3(1.0 / 3.0);
  ShadingInput s = shading_input_at(triangle, bary, triangle_point(triangle, bary), frame.eye.xyz);
  imageStore(fa_color_atlas, t, vec4(shade_surface_point(s.point, s.material, s.emission), 1.0));
  atomicAdd(fa_state.trace.w, 1u);
}
