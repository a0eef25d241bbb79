#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <atomic>
#include <random>
#include <stdexcept>
#include <vector>

#include "renderer/reference/row_threads.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(RayTetrahedron, AxisRayThroughCornerTetrahedron) {
  // Tetrahedron x, y, z >= 0, x + y + z <= 1; the ray along z at (0.2, 0.3) is inside for
  // z in [0, 0.5].
  std::array<glm::dvec3, 4> v = {glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};
  const auto in = reference::ray_tetrahedron(v, {0.2, 0.3, -1.0}, {0, 0, 1}, 0.0, kInf);
  EXPECT_NEAR(in.enter, 1.0, 1e-15);
  EXPECT_NEAR(in.exit, 1.5, 1e-15);
  std::swap(v[1], v[2]);  // the other orientation gives the same interval
  EXPECT_NEAR(reference::ray_tetrahedron(v, {0.2, 0.3, -1.0}, {0, 0, 1}, 0.0, kInf).length(), 0.5, 1e-15);
  EXPECT_TRUE(reference::ray_tetrahedron(v, {0.8, 0.3, -1.0}, {0, 0, 1}, 0.0, kInf).empty());
}

TEST(RayTetrahedron, KuhnSplitChordsSumToTheBoxChord) {
  // The six tetrahedra of a cube partition it, so the lengths through them add up to the
  // chord through the cube, for any ray.
  const TetMesh m = make_box_mesh(glm::dvec3(0), glm::dvec3(1), 1, [](const glm::dvec3&) { return 1.0; });
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 origin(u(rng), u(rng), -2.0);
    const glm::dvec3 target(u(rng), u(rng), 3.0);
    const glm::dvec3 dir = glm::normalize(target - origin);
    double sum = 0.0;
    for (const auto& t : m.tets) {
      std::array<glm::dvec3, 4> v;
      for (int k = 0; k < 4; ++k) v[k] = m.points[t[k]];
      sum += reference::ray_tetrahedron(v, origin, dir, 0.0, kInf).length();
    }
    // Chord through the slab 0 <= z <= 1 while x, y stay inside (they do for these rays
    // only if they do at both planes; otherwise clip against the box).
    double t0 = 0.0, t1 = kInf;
    for (int a = 0; a < 3; ++a) {
      if (dir[a] == 0.0) continue;
      double ta = (0.0 - origin[a]) / dir[a], tb = (1.0 - origin[a]) / dir[a];
      t0 = std::max(t0, std::min(ta, tb));
      t1 = std::min(t1, std::max(ta, tb));
    }
    EXPECT_NEAR(sum, std::max(0.0, t1 - t0), 1e-12) << "ray " << i;
  }
}

TEST(OpticalDepthImage, ConstantCubeGivesSigmaTimesChord) {
  const TetMesh m = make_box_mesh(glm::dvec3(-1), glm::dvec3(1), 2, [](const glm::dvec3&) { return 0.5; });
  Camera c;
  c.eye = {0, 0, 10};
  c.fovy_degrees = 10.0;
  const auto img = reference::optical_depth_image(m, c, 9, 9);
  // The central pixel's ray runs along the z axis through the whole cube: length 2.
  EXPECT_NEAR(img[4 * 9 + 4], 0.5 * 2.0, 1e-12);
}

TEST(RowThreads, EveryRowIsGivenToExactlyOneThreadAndFailuresComeBack) {
  for (const uint32_t rows : {1u, 2u, 3u, 7u, 1000u}) {
    std::vector<std::atomic<int>> seen(rows);
    reference::for_row_phases(rows, [&](reference::RowPhase r) {
      EXPECT_LT(r.phase, r.step);
      for (uint32_t y = r.first_from(0); y < rows; y += r.step) ++seen[y];
      // first_from lands on the thread's own rows, at or after its argument
      for (uint32_t y = 0; y < 2 * r.step + 3; ++y) {
        EXPECT_GE(r.first_from(y), y);
        EXPECT_LT(r.first_from(y), y + r.step);
        EXPECT_EQ(r.first_from(y) % r.step, r.phase);
      }
    });
    for (uint32_t y = 0; y < rows; ++y) EXPECT_EQ(seen[y].load(), 1) << "row " << y << " of " << rows;
  }
  EXPECT_THROW(reference::for_row_phases(64, [](reference::RowPhase r) {
                 if (r.phase == r.step - 1) throw std::runtime_error("row failed");
               }),
               std::runtime_error);
}

TEST(OpticalDepthImage, RowsSpreadOverThreadsSumEachPixelAsOneLoopWould) {
  // Every pixel's optical depth is the sum over cells in mesh order, bit for bit, however the
  // rows are shared out: a row visited twice or never, or a sum formed in another order, shows.
  const TetMesh m = make_box_mesh(glm::dvec3(-1), glm::dvec3(1), 3, [](const glm::dvec3& p) { return 0.7 + 0.2 * p.y; });
  Camera c;
  c.eye = {0.4, 2.5, 6.0};
  c.fovy_degrees = 35.0;
  const uint32_t w = 37, h = 29;
  const auto image = reference::optical_depth_image(m, c, w, h);
  const glm::dvec3 forward = glm::normalize(c.target - c.eye);
  size_t covered = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const glm::dvec3 dir = reference::ray_direction(c, w, h, x + 0.5, y + 0.5);
      double sum = 0.0;
      for (size_t k = 0; k < m.tets.size(); ++k) {
        std::array<glm::dvec3, 4> v;
        for (int i = 0; i < 4; ++i) v[i] = m.points[m.tets[k][i]];
        const auto in = reference::ray_tetrahedron(v, c.eye, dir, c.near_distance / glm::dot(dir, forward), kInf);
        if (!in.empty()) sum += m.cell_extinction[k] * in.length();
      }
      covered += sum > 0.0;
      EXPECT_EQ(image[size_t(y) * w + x], sum) << "pixel " << x << "," << y;
    }
  EXPECT_GT(covered, size_t(w) * h / 4);
}

TEST(SnappingVariationImage, BoundsTheWholeImageShiftAndEqualsItForOneCellAwayFromVertices) {
  // Per pixel, the per-cell sum of changes is at least the change of the sum (triangle
  // inequality); for a single cell the two agree except next to a projected vertex.
  const TetMesh cube = make_box_mesh(glm::dvec3(-1), glm::dvec3(1), 2, [](const glm::dvec3& p) { return 1.0 + 0.3 * p.x; });
  TetMesh one = cube;
  one.tets.resize(1);
  one.cell_extinction.resize(1);
  Camera c;
  c.eye = {1.3, 0.9, 5.0};
  c.fovy_degrees = 30.0;
  const uint32_t w = 24, h = 20;
  const double radius = 0.25;
  for (const TetMesh* m : {&cube, static_cast<const TetMesh*>(&one)}) {
    const auto centre = reference::optical_depth_image(*m, c, w, h);
    std::vector<double> image_shift(centre.size(), 0.0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const auto shifted = reference::optical_depth_image(*m, c, w, h, dx * radius, dy * radius);
        for (size_t i = 0; i < centre.size(); ++i) image_shift[i] = std::max(image_shift[i], std::abs(shifted[i] - centre[i]));
      }
    const auto per_cell = reference::snapping_variation_image(*m, c, w, h, radius);
    for (size_t i = 0; i < centre.size(); ++i) {
      EXPECT_GE(per_cell[i], image_shift[i] - 1e-12) << "pixel " << i;
      if (m == &one && per_cell[i] > image_shift[i] + 1e-12) {
        // Only where one of the cell's vertices projects within the radius of the centre.
        const glm::dvec3 d = reference::ray_direction(c, w, h, double(i % w) + 0.5, double(i / w) + 0.5);
        double nearest = 1e300;
        for (uint32_t k : m->tets[0]) {
          const glm::dvec3 to_vertex = glm::normalize(m->points[k] - c.eye);
          nearest = std::min(nearest, glm::length(to_vertex - d));
        }
        EXPECT_LT(nearest, 0.05) << "pixel " << i;  // a pixel here spans about 0.02 in direction
      }
    }
  }
}

TEST(SnappingVariationImage, EdgeAlongAPixelRayReachesTheEdgesChord) {
  // The edge from (0, 0, -2) to (0, 0, -3) lies on the central pixel's ray: rays just beside
  // it cross nearly the whole edge, and the variation there must reach the chord, 1.
  TetMesh m;
  m.name = "edge on";
  m.points = {glm::dvec3(0, 0, -2), glm::dvec3(0, 0, -3), glm::dvec3(0.3, 0, -2.5), glm::dvec3(0, 0.3, -2.5)};
  m.tets = {{0, 1, 2, 3}};
  m.cell_extinction = {1.0};
  Camera c;
  c.eye = {0, 0, 0};
  c.target = {0, 0, -1};
  c.fovy_degrees = 40.0;
  const auto variation = reference::snapping_variation_image(m, c, 9, 9, 1.0 / 128.0);
  EXPECT_NEAR(variation[4 * 9 + 4], 1.0, 1e-4);
}

}  // namespace
}  // namespace prismoid
