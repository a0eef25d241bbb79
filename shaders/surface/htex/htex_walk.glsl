// Walking between Htex texels across the surface: the GLSL twin of renderer/surface/htex/htex_walk.cpp
// (htex::step_texel, walk_texel) over the global tables of htex.glsl, step for step. Unit steps
// cross quad borders through the face's quarter-turn charts and the twin's flip; directions turn
// with the same maps. Tested against the C++ at many texels (tests/surface/test_htex_gi.cpp).
// Include after htex.glsl.
#ifndef PRISMOID_HTEX_WALK_GLSL
#define PRISMOID_HTEX_WALK_GLSL

struct HtexQuadTexel {
  uint edge;  // global edge = quad
  ivec2 ij;
};

// Direction maps as the columns x, y (images of (1, 0) and (0, 1)).
struct HtexDirectionMap {
  ivec2 x, y;
};
ivec2 htex_apply(HtexDirectionMap m, ivec2 d) { return d.x * m.x + d.y * m.y; }
HtexDirectionMap htex_compose(HtexDirectionMap second, HtexDirectionMap first) {
  return HtexDirectionMap(htex_apply(second, first.x), htex_apply(second, first.y));
}
const HtexDirectionMap kHtexIdentity = HtexDirectionMap(ivec2(1, 0), ivec2(0, 1));
const HtexDirectionMap kHtexFlip = HtexDirectionMap(ivec2(-1, 0), ivec2(0, -1));
const HtexDirectionMap kHtexToNext = HtexDirectionMap(ivec2(0, -1), ivec2(1, 0));
const HtexDirectionMap kHtexToPrev = HtexDirectionMap(ivec2(0, 1), ivec2(-1, 0));

bool htex_is_ghost_texel(uint n, HtexQuadTexel t) {
  return htex_twin[htex_edge_halfedge[t.edge]] < 0 && t.ij.x + t.ij.y >= int(n);
}

// One unit step along d ((+-1, 0) or (0, +-1)); false where it leaves the surface or lands on a
// ghost texel. `turn` maps directions of the old quad's frame to the new one's.
bool htex_step_texel(uint n, HtexQuadTexel from, ivec2 d, out HtexQuadTexel to, out HtexDirectionMap turn) {
  int side = int(n), last = side - 1;
  int i = from.ij.x + d.x, j = from.ij.y + d.y;
  turn = kHtexIdentity;
  to = HtexQuadTexel(from.edge, ivec2(i, j));
  if (i >= 0 && j >= 0 && i < side && j < side) return !htex_is_ghost_texel(n, to);
  int p = htex_edge_halfedge[from.edge];
  int h = p, a = i, b = j;
  HtexDirectionMap quad_to_chart = kHtexIdentity;
  if (i >= side || j >= side) {  // in the twin's half
    h = htex_twin[p];
    if (h < 0) return false;
    a = last - i;
    b = last - j;
    quad_to_chart = kHtexFlip;
  }
  int h2, a2, b2;
  HtexDirectionMap chart_to_chart;
  if (a < 0) {
    h2 = htex_next(h);
    a2 = b;
    b2 = -1 - a;
    chart_to_chart = kHtexToNext;
  } else {
    h2 = htex_prev(h);
    a2 = -1 - b;
    b2 = a;
    chart_to_chart = kHtexToPrev;
  }
  HtexDirectionMap chart_to_quad = kHtexIdentity;
  if (htex_primary(h2)) {
    to = HtexQuadTexel(htex_edge_of[h2], ivec2(a2, b2));
  } else {
    to = HtexQuadTexel(htex_edge_of[h2], ivec2(last - a2, last - b2));
    chart_to_quad = kHtexFlip;
  }
  if (htex_is_ghost_texel(n, to)) return false;
  turn = htex_compose(chart_to_quad, htex_compose(chart_to_chart, quad_to_chart));
  return true;
}

// |offset.x| steps along the start quad's i axis, then |offset.y| along its j axis (htex::walk_texel).
bool htex_walk_texel(uint n, HtexQuadTexel from, ivec2 offset, out HtexQuadTexel to) {
  to = from;
  ivec2 x_dir = ivec2(offset.x >= 0 ? 1 : -1, 0), y_dir = ivec2(0, offset.y >= 0 ? 1 : -1);
  for (int k = 0; k < abs(offset.x); ++k) {
    HtexQuadTexel next;
    HtexDirectionMap turn;
    if (!htex_step_texel(n, to, x_dir, next, turn)) return false;
    to = next;
    x_dir = htex_apply(turn, x_dir);
    y_dir = htex_apply(turn, y_dir);
  }
  for (int k = 0; k < abs(offset.y); ++k) {
    HtexQuadTexel next;
    HtexDirectionMap turn;
    if (!htex_step_texel(n, to, y_dir, next, turn)) return false;
    to = next;
    y_dir = htex_apply(turn, y_dir);
  }
  return true;
}

#endif
