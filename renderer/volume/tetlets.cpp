#include "renderer/volume/tetlets.hpp"
#include "scene/tet_mesh.hpp"

#include <algorithm>
#include <array>
#include <numeric>
#include <stdexcept>

#include <glm/common.hpp>

namespace prismoid::volume {

namespace {

// Spreads the low 10 bits of v so that two zero bits separate each (for 30-bit Morton codes).
uint32_t spread_bits(uint32_t v) {
  v &= 0x3ffu;
  v = (v | (v << 16)) & 0x030000ffu;
  v = (v | (v << 8)) & 0x0300f00fu;
  v = (v | (v << 4)) & 0x030c30c3u;
  v = (v | (v << 2)) & 0x09249249u;
  return v;
}

}  // namespace

Tetlets build_tetlets(const TetMesh& mesh, uint32_t max_cells, uint32_t max_points) {
  if (max_cells == 0 || max_points < 4 || max_points > 255)
    throw std::invalid_argument("build_tetlets: max_cells >= 1 and 4 <= max_points <= 255");
  Tetlets t;
  t.max_cells = max_cells;
  t.max_points = max_points;
  const Bounds b = bounds_of(mesh);
  const glm::dvec3 extent = glm::max(b.max - b.min, glm::dvec3(1e-300));
  std::vector<uint32_t> morton(mesh.tets.size());
  for (size_t c = 0; c < mesh.tets.size(); ++c) {
    glm::dvec3 centroid(0.0);
    for (uint32_t v : mesh.tets[c]) centroid += mesh.points[v];
    const glm::dvec3 u = glm::clamp((centroid * 0.25 - b.min) / extent, 0.0, 1.0) * 1023.0;
    morton[c] = spread_bits(uint32_t(u.x)) | (spread_bits(uint32_t(u.y)) << 1) | (spread_bits(uint32_t(u.z)) << 2);
  }
  std::vector<uint32_t> order(mesh.tets.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t c) { return morton[a] < morton[c]; });

  glm::uvec4 header(0u);  // the tetlet being filled
  auto close = [&] {
    if (header.w > 0) t.headers.push_back(header);
    header = glm::uvec4(uint32_t(t.points.size()), 0u, uint32_t(t.cells.size()), 0u);
  };
  close();
  for (uint32_t c : order) {
    // Local indices of the cell's corners, adding the points the tetlet lacks.
    auto local_of = [&](uint32_t point) -> int {
      for (uint32_t i = 0; i < header.y; ++i)
        if (t.points[header.x + i] == point) return int(i);
      return -1;
    };
    uint32_t missing = 0;
    std::array<uint32_t, 4> distinct_new{};
    for (uint32_t v : mesh.tets[c])
      if (local_of(v) < 0 && std::find(distinct_new.begin(), distinct_new.begin() + missing, v) == distinct_new.begin() + missing)
        distinct_new[missing++] = v;
    if (header.w == max_cells || header.y + missing > max_points) close();
    uint32_t packed = 0;
    for (int k = 0; k < 4; ++k) {
      int local = local_of(mesh.tets[c][k]);
      if (local < 0) {
        t.points.push_back(mesh.tets[c][k]);
        local = int(header.y++);
      }
      packed |= uint32_t(local) << (8 * k);
    }
    t.cells.emplace_back(c, packed);
    ++header.w;
  }
  close();
  return t;
}

}  // namespace prismoid::volume
