#version 460
// The lookup (FastAtlas, section 5 and appendix A): per pixel, its triangle's chart maps the
// pixel's centre into the atlas, and the four bilinear taps there are filtered with the hard-edge
// filter: a tap counts when its texel was shaded for the pixel's own triangle or for an edge
// neighbour meeting it at under 75 degrees (FaTriangleGpu), and the value is rebuilt from the taps
// that count (the CPU twin fastatlas::hard_edge_filter: nearest, one, linear, clamped barycentric,
// bilinear). Filtering is by hand in float (hardware filtering keeps only 8 bits of weight).
// A triangle too small to hold a texel centre at a low scale has no texel of its own (the paper's
// "tiny but distinct details" that downscaling drops): its pixels take the nearest texel, or the
// first tap holding any triangle; a pixel whose four taps hold none is a counted hole. The sky where no
// surface was seen (alpha 0).
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_SURFACE_VERTEX_BUFFERS
#include "../scene_bindings.glsl"
#include "../pixel_ray.glsl"
#include "fastatlas.glsl"
#include "../stretch.glsl"

layout(set = 0, binding = PRISMOID_FA_BINDING_ID_ATLAS, r32ui) uniform readonly uimage2D fa_id_atlas;
layout(set = 0, binding = PRISMOID_FA_BINDING_COLOR_ATLAS, rgba32f) uniform readonly image2D fa_color_atlas;

layout(location = 0) out vec4 out_color;

const vec2 kTapAt[4] = vec2[4](vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(0.0, 1.0), vec2(1.0, 1.0));

uint tap_id(ivec2 t) {
  if (any(lessThan(t, ivec2(0))) || any(greaterThanEqual(t, ivec2(fa_push.atlas.xy)))) return PRISMOID_FA_NONE;
  uint id = imageLoad(fa_id_atlas, t).x;
  return id == PRISMOID_FA_NONE ? id : id & PRISMOID_FA_TRIANGLE_MASK;
}

bool usable(uint triangle, uint id) {
  if (id == triangle) return true;
  if (id == PRISMOID_FA_NONE) return false;
  FaTriangleGpu tri = fa_triangles[triangle];
  for (uint k = 0u; k < 3u; ++k)
    if (tri.neighbours[k] == id && (tri.neighbours.w & (1u << k)) != 0u) return true;
  return false;
}

void main() {
  uvec2 pixel = uvec2(gl_FragCoord.xy);
  uvec4 vis = fa_visibility[pixel.y * fa_push.image.x + pixel.x];
  if (vis.x == 0u) {
    out_color = vec4(pixel_sky(gl_FragCoord.xy), 0.0);
    return;
  }
  if (fa_state.charts.z == 0u) {  // no candidate scale fits: nothing was shaded
    atomicAdd(fa_state.counts.y, 1u);
    out_color = vec4(0.0, 0.0, 0.0, 1.0);
    return;
  }
  uint triangle = vis.x - 1u;
  FaChartMap map = fa_chart_map(fa_parent[triangle]);
  vec2 u = fa_to_atlas(map, gl_FragCoord.xy) - 0.5;
  // The stretch between screen and atlas here (1 / s for every pixel, by construction: measured
  // all the same, as for the other atlases).
  float big, small;
  if (pixel_stretch(fa_to_atlas(map, gl_FragCoord.xy + vec2(1.0, 0.0)) - 0.5 - u, fa_to_atlas(map, gl_FragCoord.xy + vec2(0.0, 1.0)) - 0.5 - u,
                    big, small)) {
    uint term = stretch_sum_term(big, small);
    if (atomicAdd(fa_state.stretch.x, term) > 0xffffffffu - term) atomicAdd(fa_state.stretch.w, 1u);  // the carry
    atomicAdd(fa_state.stretch.y, 1u);
    atomicMax(fa_state.stretch.z, floatBitsToUint(big));
  }
  ivec2 base = ivec2(floor(u));
  vec2 at = u - vec2(base);
  vec3 value[4];
  uint used[4];
  uint n = 0u;
  for (uint k = 0u; k < 4u; ++k) {
    ivec2 t = base + ivec2(kTapAt[k]);
    uint id = tap_id(t);
    value[k] = id == PRISMOID_FA_NONE ? vec3(0.0) : imageLoad(fa_color_atlas, t).rgb;
    if (usable(triangle, id)) used[n++] = k;
  }
  vec3 c;
  if (n == 0u) {  // the nearest texel; where it is empty, the first tap that holds a triangle
    uint k = (at.x >= 0.5 ? 1u : 0u) + (at.y >= 0.5 ? 2u : 0u);
    for (uint j = 0u; j < 4u && tap_id(base + ivec2(kTapAt[k])) == PRISMOID_FA_NONE; ++j) k = j;
    if (tap_id(base + ivec2(kTapAt[k])) == PRISMOID_FA_NONE) atomicAdd(fa_state.counts.y, 1u);
    c = value[k];
  } else if (n == 1u) {
    c = value[used[0]];
  } else if (n == 2u) {
    vec2 a = kTapAt[used[0]], b = kTapAt[used[1]];
    float s = clamp(dot(at - a, b - a) / dot(b - a, b - a), 0.0, 1.0);
    c = mix(value[used[0]], value[used[1]], s);
  } else if (n == 3u) {
    vec2 a = kTapAt[used[0]], b = kTapAt[used[1]], d = kTapAt[used[2]];
    float area = (b.x - a.x) * (d.y - a.y) - (d.x - a.x) * (b.y - a.y);
    float lb = ((at.x - a.x) * (d.y - a.y) - (d.x - a.x) * (at.y - a.y)) / area;
    float ld = ((b.x - a.x) * (at.y - a.y) - (at.x - a.x) * (b.y - a.y)) / area;
    vec3 va = value[used[0]], vb = value[used[1]], vd = value[used[2]];
    c = clamp((1.0 - lb - ld) * va + lb * vb + ld * vd, min(va, min(vb, vd)), max(va, max(vb, vd)));
  } else {
    c = mix(mix(value[0], value[1], at.x), mix(value[2], value[3], at.x), at.y);
  }
  out_color = vec4(c, 1.0);
}
