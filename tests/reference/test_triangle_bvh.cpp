#include "renderer/reference/triangle_bvh.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/generators.hpp"

namespace prismoid::reference {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::vector<TriangleBvh::Triangle> random_triangles(size_t n, uint64_t seed, const glm::dvec3& offset = glm::dvec3(0.0)) {
  std::mt19937_64 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<TriangleBvh::Triangle> tris;
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3 c(u(gen), u(gen), u(gen));
    tris.push_back({offset + c + 0.1 * glm::dvec3(u(gen), u(gen), u(gen)), offset + c + 0.1 * glm::dvec3(u(gen), u(gen), u(gen)),
                    offset + c + 0.1 * glm::dvec3(u(gen), u(gen), u(gen))});
  }
  return tris;
}

TriangleHit brute_force(const std::vector<TriangleBvh::Triangle>& tris, const glm::dvec3& o, const glm::dvec3& d) {
  TriangleHit best;
  for (uint32_t i = 0; i < tris.size(); ++i) {
    TriangleHit h;
    if (intersect_triangle(tris[i][0], tris[i][1], tris[i][2], o, d, 0.0, best.t, h)) {
      h.triangle = i;
      best = h;
    }
  }
  return best;
}

TEST(TriangleBvh, ClosestHitMatchesBruteForce) {
  const auto tris = random_triangles(3000, 1);
  const TriangleBvh bvh(tris);
  EXPECT_EQ(bvh.skipped_triangles(), 0u);
  EXPECT_GT(bvh.node_count(), 3000u / 4u);
  EXPECT_LT(bvh.depth(), 40u);
  std::mt19937_64 gen(2);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  size_t hits = 0;
  for (int i = 0; i < 4000; ++i) {
    const glm::dvec3 o(u(gen), u(gen), u(gen));
    const glm::dvec3 d = glm::dvec3(u(gen), u(gen), u(gen));
    const TriangleHit expected = brute_force(tris, o, d);
    const TriangleHit got = bvh.closest_hit(o, d, 0.0, kInf);
    ASSERT_EQ(got.hit(), expected.hit()) << "ray " << i;
    EXPECT_EQ(bvh.occluded(o, d, 0.0, kInf), expected.hit());
    if (!expected.hit()) continue;
    ++hits;
    EXPECT_EQ(got.triangle, expected.triangle);
    EXPECT_EQ(got.t, expected.t);
    // The occlusion query honours its range: nothing strictly before the closest hit.
    EXPECT_FALSE(bvh.occluded(o, d, 0.0, expected.t * (1.0 - 1e-12)));
  }
  EXPECT_GT(hits, 1000u);
}

TEST(TriangleBvh, HitPointAndBarycentricsAreExactForAKnownTriangle) {
  const TriangleBvh bvh({{glm::dvec3(0, 0, 0), glm::dvec3(4, 0, 0), glm::dvec3(0, 2, 0)}});
  const TriangleHit h = bvh.closest_hit({1.0, 0.5, 3.0}, {0, 0, -2}, 0.0, kInf);
  ASSERT_TRUE(h.hit());
  EXPECT_DOUBLE_EQ(h.t, 1.5);
  EXPECT_DOUBLE_EQ(h.b1, 0.25);  // x = 4 b1
  EXPECT_DOUBLE_EQ(h.b2, 0.25);  // y = 2 b2
  // Both sides hit (the test is not culling).
  EXPECT_TRUE(bvh.closest_hit({1.0, 0.5, -3.0}, {0, 0, 1}, 0.0, kInf).hit());
  // A range that ends before the triangle, or starts after it, misses it.
  EXPECT_FALSE(bvh.closest_hit({1.0, 0.5, 3.0}, {0, 0, -2}, 0.0, 1.5).hit());
  EXPECT_FALSE(bvh.closest_hit({1.0, 0.5, 3.0}, {0, 0, -2}, 1.5, kInf).hit());
  // Skipped triangles are not hit.
  EXPECT_FALSE(bvh.closest_hit({1.0, 0.5, 3.0}, {0, 0, -2}, 0.0, kInf, 0).hit());
  EXPECT_FALSE(bvh.occluded({1.0, 0.5, 3.0}, {0, 0, -2}, 0.0, kInf, kNoTriangle, 0));
}

TEST(TriangleBvh, RaysThroughSharedEdgesAndVerticesNeverLeak) {
  // A closed icosphere: rays from inside aimed exactly at every vertex and edge midpoint, where
  // two or more triangles meet, must hit one of them (Woop et al.'s watertightness).
  const SurfaceMesh sphere = make_icosphere(glm::dvec3(0.3, -0.2, 0.1), 1.0, 3);
  std::vector<TriangleBvh::Triangle> tris;
  for (const auto& t : sphere.triangles) tris.push_back({sphere.points[t[0]], sphere.points[t[1]], sphere.points[t[2]]});
  const TriangleBvh bvh(tris);
  std::vector<glm::dvec3> targets = sphere.points;
  for (const auto& t : sphere.triangles)
    for (int k = 0; k < 3; ++k) targets.push_back(0.5 * (sphere.points[t[size_t(k)]] + sphere.points[t[size_t((k + 1) % 3)]]));
  size_t misses = 0;
  for (const glm::dvec3& origin : {glm::dvec3(0.3, -0.2, 0.1), glm::dvec3(0.0), glm::dvec3(0.7, 0.3, -0.4)})
    for (const auto& target : targets)
      if (!bvh.closest_hit(origin, target - origin, 0.0, kInf).hit()) ++misses;
  EXPECT_EQ(misses, 0u);

  // A flat grid of right triangles hit straight on through its vertices and edges.
  std::vector<TriangleBvh::Triangle> grid;
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j) {
      const glm::dvec3 a(i, j, 0), b(i + 1, j, 0), c(i + 1, j + 1, 0), d(i, j + 1, 0);
      grid.push_back({a, b, c});
      grid.push_back({a, c, d});
    }
  const TriangleBvh flat(grid);
  for (int i = 0; i <= 16; ++i)
    for (int j = 0; j <= 16; ++j) {
      const glm::dvec3 o(i * 0.5, j * 0.5, 1.0);
      EXPECT_TRUE(flat.closest_hit(o, {0.0, 0.0, -1.0}, 0.0, kInf).hit()) << o.x << "," << o.y;
      // Tilted by 1e-17 (the shear sees it): inside the grid it must still hit.
      if (i > 0 && i < 16 && j > 0 && j < 16) {
        EXPECT_TRUE(flat.closest_hit(o, {1e-17, -1e-17, -1.0}, 0.0, kInf).hit()) << o.x << "," << o.y;
      }
    }
}

TEST(TriangleBvh, DegenerateTrianglesAreSkippedAndNeverHit) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<TriangleBvh::Triangle> tris = {
      {glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 0)},           // a point
      {glm::dvec3(-1, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(1, 0, 0)},          // repeated vertex
      {glm::dvec3(-1, -1, 0), glm::dvec3(0, 0, 0), glm::dvec3(1, 1, 0)},         // collinear
      {glm::dvec3(nan, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)},         // not finite
      {glm::dvec3(-2, -2, -5), glm::dvec3(2, -2, -5), glm::dvec3(0, 2, -5)},     // a real one behind them
  };
  const TriangleBvh bvh(tris);
  EXPECT_EQ(bvh.skipped_triangles(), 4u);
  for (int k = 0; k < 3; ++k) {
    TriangleHit h;
    EXPECT_FALSE(intersect_triangle(tris[size_t(k)][0], tris[size_t(k)][1], tris[size_t(k)][2], {0, 0, 1}, {0, 0, -1}, 0.0, kInf, h));
  }
  // Rays through the degenerate ones reach the real triangle, with a finite distance.
  for (const glm::dvec3& o : {glm::dvec3(0, 0, 1), glm::dvec3(0.5, 0, 1), glm::dvec3(0.5, 0.5, 1)}) {
    const TriangleHit h = bvh.closest_hit(o, {0, 0, -1}, 0.0, kInf);
    ASSERT_TRUE(h.hit());
    EXPECT_EQ(h.triangle, 4u);
    EXPECT_DOUBLE_EQ(h.t, 6.0);
  }
  // A ray in the plane of a triangle (edge-on) misses it without NaN.
  TriangleHit h;
  EXPECT_FALSE(intersect_triangle(tris[4][0], tris[4][1], tris[4][2], {-5, 0, -5}, {1, 0, 0}, 0.0, kInf, h));
  // Zero and non-finite directions hit nothing.
  EXPECT_FALSE(bvh.closest_hit({0, 0, 1}, {0, 0, 0}, 0.0, kInf).hit());
  EXPECT_FALSE(bvh.closest_hit({0, 0, 1}, {0, nan, -1}, 0.0, kInf).hit());
  // An empty hierarchy answers too.
  EXPECT_FALSE(TriangleBvh({}).closest_hit({0, 0, 0}, {1, 0, 0}, 0.0, kInf).hit());
}

TEST(TriangleBvh, FarFromTheOriginGivesTheSameHits) {
  // The same triangles and rays moved by 1e6: the same triangles are hit at the same distances
  // to within the rounding of the moved coordinates (1e6 * 2^-52 ~ 2e-10).
  const glm::dvec3 offset(1e6, -1e6, 1e6);
  const auto near = random_triangles(1500, 5);
  const auto far = random_triangles(1500, 5, offset);
  const TriangleBvh a(near), b(far);
  std::mt19937_64 gen(6);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  size_t same = 0, hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 o(u(gen), u(gen), u(gen)), d(u(gen), u(gen), u(gen));
    const TriangleHit ha = a.closest_hit(o, d, 0.0, kInf), hb = b.closest_hit(o + offset, d, 0.0, kInf);
    if (!ha.hit() && !hb.hit()) continue;
    ++hits;
    if (ha.hit() && hb.hit() && ha.triangle == hb.triangle) {
      ++same;
      EXPECT_NEAR(ha.t, hb.t, 1e-8 * std::max(1.0, ha.t));
    }
  }
  // Only rays grazing an edge within ~1e-9 could differ: none of 2000 random ones should.
  EXPECT_EQ(same, hits);
  EXPECT_GT(hits, 250u);
}

}  // namespace
}  // namespace prismoid::reference
