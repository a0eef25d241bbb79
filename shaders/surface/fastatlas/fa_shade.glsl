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
layout(set = 0, binding = PRISMOID_FA_BINDING_PREV_COLOR, rgba32f) uniform readonly image2D fa_prev_color;
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_PREV_PARENT) readonly buffer FaPrevParentBuffer { uint fa_prev_parent[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_PREV_BOXES) readonly buffer FaPrevBoxBuffer { ivec4 fa_prev_boxes[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_PREV_PLACED) readonly buffer FaPrevPlacedBuffer { uvec4 fa_prev_placed[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_PREV_STATE) readonly buffer FaPrevStateBuffer { FaStateGpu fa_prev_state; };
layout(set = 0, binding = PRISMOID_FA_BINDING_PREV_FRAME) uniform FaPrevFrameBlock { SurfaceFrame fa_prev_frame; };

// Temporal reuse (appendix D): the shading the last frame's atlas holds for surface point p of
// `triangle` (scene-local), where the last frame saw that triangle and the texel under p's place
// there was shaded for it (its alpha holds triangle + 1); false where it cannot tell. The shading
// of the last view is kept as it was (the paper's approximation: a moving eye's view-dependent
// terms lag by the frames since the last refresh).
bool fa_last_shading(uint triangle, vec3 p, out vec4 value) {
  uint root = fa_prev_parent[triangle];
  if (root == PRISMOID_FA_NONE || fa_prev_state.charts.z != 1u) return false;
  vec4 clip = fa_prev_frame.projection * (fa_prev_frame.view * vec4(p, 1.0));
  if (!(clip.w > 0.0)) return false;
  vec2 pixel = (clip.xy / clip.w + 1.0) * 0.5 * fa_prev_frame.viewport.xy;
  ivec4 box = fa_prev_boxes[root];
  uvec4 placed = fa_prev_placed[root];
  float scale = float(fa_scales[min(fa_prev_state.charts.y, PRISMOID_FA_MAX_CANDIDATES - 1u)]) / float(PRISMOID_FA_SCALE_ONE);
  vec2 d = (pixel - vec2(box.xy)) * scale;
  vec2 u = vec2(placed.xy) + 0.5 * (float(fa_push.atlas.z) - scale) + ((placed.z >> 31) != 0u ? d.yx : d);
  ivec2 q = ivec2(floor(u));
  if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, ivec2(fa_push.atlas.xy)))) return false;
  value = imageLoad(fa_prev_color, q);
  return value.a == float(triangle + 1u);
}

// The barycentrics of the point of `triangle` nearest to the point of its plane with barycentrics
// `b` (Ericson, Real-Time Collision Detection, 5.1.5: the Voronoi regions of the corners and edges).
vec3 nearest_on_triangle(uint triangle, vec3 b) {
  vec3 a = triangle_corner(triangle, 0u), bb = triangle_corner(triangle, 1u), c = triangle_corner(triangle, 2u);
  vec3 p = b.x * a + b.y * bb + b.z * c;
  vec3 ab = bb - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return vec3(1.0, 0.0, 0.0);
  vec3 bp = p - bb;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return vec3(0.0, 1.0, 0.0);
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    float v = d1 / (d1 - d3);
    return vec3(1.0 - v, v, 0.0);
  }
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return vec3(0.0, 0.0, 1.0);
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    float w = d2 / (d2 - d6);
    return vec3(1.0 - w, 0.0, w);
  }
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return vec3(0.0, 1.0 - w, w);
  }
  return clamp_to_triangle(b);  // inside (rounding): its own weights, held to the triangle
}

void main() {
  ivec2 t = ivec2(gl_LaunchIDEXT.xy);
  uint id = imageLoad(fa_id_atlas, t).x;
  if (id == PRISMOID_FA_NONE) return;
  uint triangle = id & PRISMOID_FA_TRIANGLE_MASK;
  FaChartMap map = fa_chart_map(fa_parent[triangle]);
  vec2 pixel = fa_to_screen(map, vec2(t) + 0.5);
  vec3 bary;
  if (!pixel_barycentrics(triangle, pixel, bary)) bary = vec3(1.0 / 3.0);
  // A border texel is shaded where its pixel ray meets the triangle's plane outside the triangle,
  // so that the filter's taps extrapolate across the edge. Below half a texel per pixel a texel
  // spans more than two pixels, and that point can lie far off the surface (beyond a wall of a
  // room, in its shadow: whole walls went black at scale 0.01): there it is held to the triangle.
  // The point it is held to is the triangle's nearest to where it would have extrapolated.
  if (map.scale < PRISMOID_FA_EXTRAPOLATE_SCALE && any(lessThan(bary, vec3(0.0)))) bary = nearest_on_triangle(triangle, bary);
  vec3 p = triangle_point(triangle, bary);
  vec4 last;
  if ((fa_push.image.z & PRISMOID_FA_FLAG_TEMPORAL) != 0u && fa_last_shading(triangle, p, last)) {
    imageStore(fa_color_atlas, t, last);
    atomicAdd(fa_state.copy.w, 1u);
    return;
  }
  ShadingInput s = shading_input_at(triangle, bary, p, frame.eye.xyz);
  // Alpha: the triangle + 1 (exact in float up to 2^24 triangles), for temporal reuse's check.
  imageStore(fa_color_atlas, t, vec4(shade_surface_point(s.point, s.material, s.emission), float(triangle + 1u)));
  atomicAdd(fa_state.trace.w, 1u);
}
