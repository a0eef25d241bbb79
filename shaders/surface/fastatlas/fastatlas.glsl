// The FastAtlas backend's buffers and rules (Real-Time Compact Atlases for Texture Space
// Shading), shared by its passes. Each rule has a CPU twin in renderer/surface/fastatlas/:
// the union-find (charts.cpp), the packing (atlas_packing.cpp), the chart map (atlas_map.cpp)
// and the hard-edge filter (atlas_filter.cpp).
#ifndef PRISMOID_FASTATLAS_GLSL
#define PRISMOID_FASTATLAS_GLSL

#include "../../shared/fastatlas.h"

layout(std430, set = 0, binding = PRISMOID_FA_BINDING_TRIANGLES) readonly buffer FaTriangleBuffer { FaTriangleGpu fa_triangles[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_PARENT) coherent buffer FaParentBuffer { uint fa_parent[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_VERTEX_FIRST) buffer FaVertexFirstBuffer { uint fa_vertex_first[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_BOXES) buffer FaBoxBuffer { ivec4 fa_boxes[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_KEYS) buffer FaKeyBuffer { uint fa_keys[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_CHARTS) buffer FaChartBuffer { uint fa_charts[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_PLACED) buffer FaPlacedBuffer { uvec4 fa_placed[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_CANDIDATES) buffer FaCandidateBuffer { uvec4 fa_candidates[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_FRONT) coherent buffer FaFrontBuffer { uint fa_front[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_STATE) buffer FaStateBuffer { FaStateGpu fa_state; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_VISIBILITY) buffer FaVisibilityBuffer { uvec4 fa_visibility[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_SCALES) readonly buffer FaScaleBuffer { uint fa_scales[]; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_HISTORY) buffer FaHistoryBuffer { uvec4 fa_history; };
layout(std430, set = 0, binding = PRISMOID_FA_BINDING_VISIBLE) buffer FaVisibleBuffer { uint fa_visible[]; };

layout(push_constant) uniform FaPushBlock { FaPush fa_push; };

// The root of x's set (path halving: every parent read is an earlier or equal root, since hooks
// only ever point a root at a lower one).
uint fa_find(uint x) {
  uint p = fa_parent[x];
  while (p != x) {
    uint g = fa_parent[p];
    if (g != p) atomicMin(fa_parent[x], g);
    x = p;
    p = g;
  }
  return x;
}

// Joins the sets of a and b: the higher root is hooked under the lower (one compare-and-swap
// that fails when another invocation hooked it first; then again from the new roots). The
// component's root is therefore its lowest triangle whatever the order, as the CPU twin's.
void fa_unite(uint a, uint b) {
  for (;;) {
    a = fa_find(a);
    b = fa_find(b);
    if (a == b) return;
    if (a > b) {
      uint t = a;
      a = b;
      b = t;
    }
    if (atomicCompSwap(fa_parent[b], b, a) == b) return;
  }
}

// The chart's box corner (whole pixels) and size; turned: the packer swapped its axes.
struct FaChartMap {
  vec2 screen_origin;  // pixels
  vec2 atlas_origin;   // texels: the placed box's corner + (border - scale) / 2 (atlas_map.cpp)
  float scale;         // texels per pixel
  bool turned;
};

float fa_chosen_scale() { return float(fa_scales[min(fa_state.charts.y, PRISMOID_FA_MAX_CANDIDATES - 1u)]) / float(PRISMOID_FA_SCALE_ONE); }

FaChartMap fa_chart_map(uint root) {
  FaChartMap m;
  ivec4 b = fa_boxes[root];
  uvec4 p = fa_placed[root];
  m.scale = fa_chosen_scale();
  m.screen_origin = vec2(b.xy);
  m.atlas_origin = vec2(p.xy) + 0.5 * (float(fa_push.atlas.z) - m.scale);
  m.turned = (p.z >> 31) != 0u;
  return m;
}

vec2 fa_to_atlas(FaChartMap m, vec2 pixel) {
  vec2 d = (pixel - m.screen_origin) * m.scale;
  return m.atlas_origin + (m.turned ? d.yx : d);
}

vec2 fa_to_screen(FaChartMap m, vec2 texel) {
  vec2 d = (texel - m.atlas_origin) / m.scale;
  return m.screen_origin + (m.turned ? d.yx : d);
}

#endif
