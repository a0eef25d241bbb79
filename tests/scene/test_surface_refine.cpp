// Large triangles split for a view (scene/surface_refine.hpp): afterwards none is large; the mesh
// stays closed and conforming (every edge of a closed mesh still has exactly two triangles: no
// T-junction); area, orientation and attributes carry over; what the camera cannot see and small
// triangles stay; careless and hostile arguments are refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "scene/surface_refine.hpp"

namespace prismoid {
namespace {

// The largest extent, across or down an image of w x h pixels, of the points of triangle
// (a, b, c) on a barycentric grid that lie inside the camera's view frustum: a lower bound of
// what refine_large_triangles measures by clipping.
double sampled_extent(const Camera& c, uint32_t w, uint32_t h, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& p2) {
  const glm::dvec3 fwd = glm::normalize(c.target - c.eye), right = glm::normalize(glm::cross(fwd, c.up)), up = glm::cross(right, fwd);
  const double ty = std::tan(glm::radians(c.fovy_degrees) * 0.5), tx = ty * w / h;
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  constexpr int n = 24;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; i + j <= n; ++j) {
      const glm::dvec3 q = a + (b - a) * (double(i) / n) + (p2 - a) * (double(j) / n) - c.eye;
      const double z = glm::dot(q, fwd), x = glm::dot(q, right), y = glm::dot(q, up);
      if (z < c.near_distance || std::abs(x) > z * tx || std::abs(y) > z * ty) continue;
      const glm::dvec2 px(x / (z * tx) * 0.5 * w, y / (z * ty) * 0.5 * h);
      lo = glm::min(lo, px);
      hi = glm::max(hi, px);
    }
  return hi.x >= lo.x ? std::max(hi.x - lo.x, hi.y - lo.y) : 0.0;
}

glm::dvec3 area_vector(const SceneMesh& m) {
  glm::dvec3 sum(0.0);
  for (const auto& t : m.triangles) sum += 0.5 * glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
  return sum;
}

double area(const SceneMesh& m) {
  double sum = 0.0;
  for (const auto& t : m.triangles) sum += 0.5 * glm::length(glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
  return sum;
}

TEST(SurfaceRefine, NoTriangleIsLargeAfterwardsAndTheBoxKeepsItsArea) {
  const SurfaceScene box = make_cornell_box();
  RefineStats stats;
  const SurfaceScene out = refine_large_triangles(box, box.camera, 640, 480, 24.0, &stats);
  EXPECT_GT(stats.triangles_after, 20 * stats.triangles_before);
  EXPECT_GT(stats.rounds, 2u);
  ASSERT_EQ(out.meshes.size(), box.meshes.size());
  for (size_t i = 0; i < out.meshes.size(); ++i) {
    const SceneMesh& m = out.meshes[i];
    EXPECT_NEAR(area(m), area(box.meshes[i]), 1e-12 * area(box.meshes[i])) << m.name;
    const glm::dvec3 a = area_vector(m), b = area_vector(box.meshes[i]);
    EXPECT_NEAR(glm::length(a - b), 0.0, 1e-12 * std::max(1.0, glm::length(b))) << m.name;  // the same winding
    EXPECT_EQ(m.material, box.meshes[i].material);
    if (box.materials[m.material].emission != glm::dvec3(0.0)) {
      EXPECT_EQ(m.triangles, box.meshes[i].triangles) << m.name << ": an emitter stays as it is";
    } else {
      for (const auto& t : m.triangles) EXPECT_LE(sampled_extent(box.camera, 640, 480, m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]), 24.0) << m.name;
    }
  }
}

TEST(SurfaceRefine, AClosedMeshStaysClosedAndConformingWithItsNormals) {
  SurfaceScene ball = make_furnace(0.5, 1.0, 1);  // a closed icosphere, the camera inside
  for (SurfaceMaterial& mat : ball.materials) mat.emission = glm::dvec3(0.0);  // emitters stay as they are
  SceneMesh& in = ball.meshes.at(0);
  if (in.normals.empty())
    for (const glm::dvec3& p : in.positions) in.normals.push_back(glm::normalize(p));
  const SurfaceScene out = refine_large_triangles(ball, ball.camera, 300, 300, 40.0);
  const SceneMesh& m = out.meshes.at(0);
  ASSERT_GT(m.triangles.size(), 2 * in.triangles.size());
  std::map<std::pair<uint32_t, uint32_t>, int> uses;  // directed edges
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++uses[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : uses) {
    EXPECT_EQ(n, 1) << "edge " << e.first << "-" << e.second << " used twice the same way";
    EXPECT_EQ(uses.count({e.second, e.first}), 1u) << "edge " << e.first << "-" << e.second << " has no twin: a T-junction or a hole";
  }
  ASSERT_EQ(m.normals.size(), m.positions.size());
  for (const glm::dvec3& n : m.normals) EXPECT_NEAR(glm::length(n), 1.0, 1e-12);
  EXPECT_NEAR(glm::length(area_vector(m)), 0.0, 1e-12);  // closed: the area vectors cancel
}

TEST(SurfaceRefine, ColoursFollowTheirVerticesAndTriangles) {
  SurfaceScene s = make_cornell_box();
  s.meshes.resize(1);
  SceneMesh& m = s.meshes[0];
  for (size_t i = 0; i < m.positions.size(); ++i) m.colors.push_back(glm::dvec3(double(i), 0.0, 1.0));
  m.color_binding = ColorBinding::PerVertex;
  const SurfaceScene v = refine_large_triangles(s, s.camera, 320, 240, 30.0);
  const SceneMesh& vm = v.meshes[0];
  ASSERT_GT(vm.triangles.size(), 4 * m.triangles.size());
  ASSERT_EQ(vm.colors.size(), vm.positions.size());
  // A vertex's colour is linear in its position along the original edges: each new one is the
  // mean of its edge's ends, so colour.z stays 1 and colour.x lies between the originals'.
  for (const glm::dvec3& c : vm.colors) {
    EXPECT_EQ(c.z, 1.0);
    EXPECT_GE(c.x, 0.0);
    EXPECT_LE(c.x, double(m.positions.size() - 1));
  }
  m.colors.clear();
  for (size_t i = 0; i < m.triangles.size(); ++i) m.colors.push_back(glm::dvec3(double(i), 2.0, 3.0));
  m.color_binding = ColorBinding::PerTriangle;
  const SurfaceScene t = refine_large_triangles(s, s.camera, 320, 240, 30.0);
  ASSERT_EQ(t.meshes[0].colors.size(), t.meshes[0].triangles.size());
  std::map<double, double> area_of_colour;  // each original triangle's colour covers its area
  const SceneMesh& tm = t.meshes[0];
  for (size_t i = 0; i < tm.triangles.size(); ++i) {
    const auto& tri = tm.triangles[i];
    area_of_colour[tm.colors[i].x] += 0.5 * glm::length(glm::cross(tm.positions[tri[1]] - tm.positions[tri[0]], tm.positions[tri[2]] - tm.positions[tri[0]]));
  }
  for (size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& tri = m.triangles[i];
    const double a = 0.5 * glm::length(glm::cross(m.positions[tri[1]] - m.positions[tri[0]], m.positions[tri[2]] - m.positions[tri[0]]));
    EXPECT_NEAR(area_of_colour[double(i)], a, 1e-12 * std::max(1.0, a)) << "triangle " << i;
  }
}

TEST(SurfaceRefine, SmallTrianglesAndWhatTheCameraCannotSeeStay) {
  const SurfaceScene box = make_cornell_box();
  RefineStats stats;
  const SurfaceScene same = refine_large_triangles(box, box.camera, 8, 8, 1000.0, &stats);  // every triangle small
  EXPECT_EQ(stats.rounds, 0u);
  for (size_t i = 0; i < box.meshes.size(); ++i) {
    EXPECT_EQ(same.meshes[i].triangles, box.meshes[i].triangles);
    EXPECT_EQ(same.meshes[i].positions, box.meshes[i].positions);
  }
  // The camera turned away: the whole box lies behind it.
  Camera away = box.camera;
  away.target = away.eye + (away.eye - box.camera.target);
  const SurfaceScene behind = refine_large_triangles(box, away, 1920, 1080, 1.0, &stats);
  EXPECT_EQ(stats.split_edges, 0u);
}

TEST(SurfaceRefine, CarelessAndHostileArgumentsAreRefusedByName) {
  const SurfaceScene box = make_cornell_box();
  for (double bad : {0.0, -3.0, std::nan(""), double(INFINITY)}) {
    try {
      refine_large_triangles(box, box.camera, 640, 480, bad);
      ADD_FAILURE() << bad << " was taken";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--max-triangle-pixels"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(refine_large_triangles(box, box.camera, 640, 0, 10.0), InputError);
  EXPECT_THROW(refine_large_triangles(box, box.camera, 0, 480, 10.0), InputError);
  try {  // a tiny edge limit: the cap stops it before memory runs out
    refine_large_triangles(box, box.camera, 3840, 2160, 0.01, nullptr, 100000);
    ADD_FAILURE() << "no cap";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("more than"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace prismoid
