#include "renderer/surface/fastatlas/atlas_filter.hpp"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace prismoid::fastatlas {

namespace {

const std::array<glm::dvec2, 4> kTapAt = {glm::dvec2(0, 0), glm::dvec2(1, 0), glm::dvec2(0, 1), glm::dvec2(1, 1)};

}  // namespace

glm::dvec3 hard_edge_filter(const FilterTaps& taps, const glm::dvec2& at) {
  int used[4];
  int n = 0;
  for (int i = 0; i < 4; ++i)
    if (taps.usable[i]) used[n++] = i;
  if (n == 0) {  // the nearest texel
    int i = (at.x >= 0.5 ? 1 : 0) + (at.y >= 0.5 ? 2 : 0);
    for (int j = 0; j < 4 && !taps.held[size_t(i)]; ++j) i = j;
    return taps.value[size_t(i)];
  }
  if (n == 1) return taps.value[used[0]];
  if (n == 2) {
    const glm::dvec2 a = kTapAt[used[0]], b = kTapAt[used[1]];
    const double t = std::clamp(glm::dot(at - a, b - a) / glm::dot(b - a, b - a), 0.0, 1.0);
    return glm::mix(taps.value[used[0]], taps.value[used[1]], t);
  }
  if (n == 3) {
    const glm::dvec2 a = kTapAt[used[0]], b = kTapAt[used[1]], c = kTapAt[used[2]];
    const double area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);  // +-1 for three corners of the unit square
    const double lb = ((at.x - a.x) * (c.y - a.y) - (c.x - a.x) * (at.y - a.y)) / area;
    const double lc = ((b.x - a.x) * (at.y - a.y) - (at.x - a.x) * (b.y - a.y)) / area;
    const glm::dvec3 va = taps.value[used[0]], vb = taps.value[used[1]], vc = taps.value[used[2]];
    const glm::dvec3 v = (1.0 - lb - lc) * va + lb * vb + lc * vc;
    return glm::clamp(v, glm::min(va, glm::min(vb, vc)), glm::max(va, glm::max(vb, vc)));
  }
  const glm::dvec3 bottom = glm::mix(taps.value[0], taps.value[1], at.x), top = glm::mix(taps.value[2], taps.value[3], at.x);
  return glm::mix(bottom, top, at.y);
}

bool tap_usable(bool same_triangle, bool edge_neighbour, const glm::dvec3& own_normal, const glm::dvec3& tap_normal,
                double max_degrees) {
  if (same_triangle) return true;
  if (!edge_neighbour) return false;
  return glm::dot(own_normal, tap_normal) > std::cos(glm::radians(max_degrees));
}

}  // namespace prismoid::fastatlas
