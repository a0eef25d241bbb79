#include "renderer/surface/htex/htex_walk.hpp"

#include <cstdlib>
#include <stdexcept>

namespace prismoid::htex {

namespace {

DirectionMap compose(const DirectionMap& second, const DirectionMap& first) { return {second(first.x), second(first.y)}; }

constexpr DirectionMap kIdentity{{1, 0}, {0, 1}};
constexpr DirectionMap kFlip{{-1, 0}, {0, -1}};       // quad <-> twin chart: (u, v) = (1 - x, 1 - y)
constexpr DirectionMap kToNext{{0, -1}, {1, 0}};      // (du, dv) -> (dv, -du)
constexpr DirectionMap kToPrev{{0, 1}, {-1, 0}};      // (du, dv) -> (-dv, du)

// Chart texel (a, b) of halfedge h -> its quad's texel, and the direction map chart -> quad.
TexelStep chart_to_quad(const HalfedgeMesh& mesh, uint32_t n, int32_t h, int32_t a, int32_t b) {
  const int32_t last = static_cast<int32_t>(n) - 1;
  if (mesh.primary(h)) return {{mesh.edge_of[h], a, b}, kIdentity};
  return {{mesh.edge_of[h], last - a, last - b}, kFlip};
}

}  // namespace

bool is_ghost_texel(const HalfedgeMesh& mesh, uint32_t n, const QuadTexel& t) {
  return mesh.twin[mesh.edge_halfedge[t.edge]] == kNoHalfedge && t.i + t.j >= static_cast<int32_t>(n);
}

std::optional<TexelStep> step_texel(const HalfedgeMesh& mesh, uint32_t n, const QuadTexel& from, const glm::ivec2& d) {
  if (std::abs(d.x) + std::abs(d.y) != 1) throw std::invalid_argument("htex walk: a step is one texel along one axis");
  const int32_t side = static_cast<int32_t>(n), last = side - 1;
  const int32_t i = from.i + d.x, j = from.j + d.y;
  if (i >= 0 && j >= 0 && i < side && j < side) {
    const QuadTexel t{from.edge, i, j};
    if (is_ghost_texel(mesh, n, t)) return std::nullopt;
    return TexelStep{t, kIdentity};
  }
  const int32_t p = mesh.edge_halfedge[from.edge];
  // The halfedge whose chart holds (i, j), the chart texel there, and quad -> chart directions.
  int32_t h = p, a = i, b = j;
  DirectionMap quad_to_chart = kIdentity;
  if (i >= side || j >= side) {  // in the twin's half
    h = mesh.twin[p];
    if (h == kNoHalfedge) return std::nullopt;
    a = last - i;
    b = last - j;
    quad_to_chart = kFlip;
  }
  // Leave the chart across its side u = 0 (a < 0) or v = 0 (b < 0).
  int32_t h2 = 0, a2 = 0, b2 = 0;
  DirectionMap chart_to_chart;
  if (a < 0) {
    h2 = HalfedgeMesh::next(h);
    a2 = b;
    b2 = -1 - a;
    chart_to_chart = kToNext;
  } else {
    h2 = HalfedgeMesh::prev(h);
    a2 = -1 - b;
    b2 = a;
    chart_to_chart = kToPrev;
  }
  TexelStep step = chart_to_quad(mesh, n, h2, a2, b2);
  if (is_ghost_texel(mesh, n, step.texel)) return std::nullopt;
  step.turn = compose(step.turn, compose(chart_to_chart, quad_to_chart));
  return step;
}

std::optional<QuadTexel> walk_texel(const HalfedgeMesh& mesh, uint32_t n, const QuadTexel& from, const glm::ivec2& offset) {
  QuadTexel at = from;
  glm::ivec2 x_dir(offset.x >= 0 ? 1 : -1, 0), y_dir(0, offset.y >= 0 ? 1 : -1);
  for (int k = 0; k < std::abs(offset.x); ++k) {
    const auto s = step_texel(mesh, n, at, x_dir);
    if (!s) return std::nullopt;
    at = s->texel;
    x_dir = s->turn(x_dir);
    y_dir = s->turn(y_dir);
  }
  for (int k = 0; k < std::abs(offset.y); ++k) {
    const auto s = step_texel(mesh, n, at, y_dir);
    if (!s) return std::nullopt;
    at = s->texel;
    y_dir = s->turn(y_dir);
  }
  return at;
}

}  // namespace prismoid::htex
