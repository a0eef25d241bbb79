// Tetlets: every cell in exactly one group, corners that point at the right points, groups
// within their limits, and points actually shared.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>

#include "renderer/volume/tetlets.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {
namespace {

void expect_valid(const TetMesh& mesh, const Tetlets& t) {
  std::vector<int> seen(mesh.tets.size(), 0);
  size_t cells = 0;
  for (const glm::uvec4& h : t.headers) {
    EXPECT_GE(h.w, 1u);
    EXPECT_LE(h.w, t.max_cells);
    EXPECT_LE(h.y, t.max_points);
    std::set<uint32_t> distinct(t.points.begin() + h.x, t.points.begin() + h.x + h.y);
    EXPECT_EQ(distinct.size(), h.y) << "a point listed twice in one tetlet";
    for (uint32_t k = 0; k < h.w; ++k) {
      const glm::uvec2 entry = t.cells[h.z + k];
      ASSERT_LT(entry.x, mesh.tets.size());
      ++seen[entry.x];
      for (int corner = 0; corner < 4; ++corner) {
        const uint32_t local = (entry.y >> (8 * corner)) & 0xffu;
        ASSERT_LT(local, h.y);
        EXPECT_EQ(t.points[h.x + local], mesh.tets[entry.x][corner]) << "cell " << entry.x << " corner " << corner;
      }
    }
    cells += h.w;
  }
  EXPECT_EQ(cells, mesh.tets.size());
  for (size_t c = 0; c < seen.size(); ++c) EXPECT_EQ(seen[c], 1) << "cell " << c;
}

TEST(Tetlets, EveryCellOnceWithCornersMappedAndLimitsKept) {
  const TetMesh mesh = make_box_mesh(glm::dvec3(-1), glm::dvec3(1), 8, [](const glm::dvec3&) { return 1.0; });
  for (uint32_t size : {1u, 4u, 8u, 16u}) {
    const Tetlets t = build_tetlets(mesh, size, 64);
    expect_valid(mesh, t);
    std::printf("tetlets of %u cells: %zu tetlets, %.2f points loaded per cell (4 without sharing)\n", size, t.headers.size(),
                t.points_per_cell());
    if (size == 1) {
      EXPECT_DOUBLE_EQ(t.points_per_cell(), 4.0);
    }
    if (size == 16) {
      // 16 neighbouring Kuhn cells (about 2.7 cubes) touch far fewer than 64 points: sharing must
      // at least halve the loads.
      EXPECT_LT(t.points_per_cell(), 2.0);
    }
  }
}

TEST(Tetlets, TightPointLimitStartsNewTetlets) {
  const TetMesh mesh = make_box_mesh(glm::dvec3(0), glm::dvec3(1), 4, [](const glm::dvec3&) { return 1.0; });
  const Tetlets t = build_tetlets(mesh, 16, 6);
  expect_valid(mesh, t);
  for (const auto& h : t.headers) EXPECT_LE(h.y, 6u);
}

TEST(Tetlets, RepeatedPointsAndEmptyMeshes) {
  TetMesh mesh;
  mesh.points = {glm::dvec3(0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)};
  mesh.tets = {{0, 1, 1, 2}};  // a flat cell with a repeated point
  mesh.cell_extinction = {1.0};
  const Tetlets t = build_tetlets(mesh, 4, 64);
  expect_valid(mesh, t);
  EXPECT_EQ(t.points.size(), 3u);
  TetMesh empty;
  EXPECT_TRUE(build_tetlets(empty, 4, 64).headers.empty());
}

}  // namespace
}  // namespace prismoid::volume
