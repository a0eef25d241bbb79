// Meshlets and their charts (renderer/surface/msa/meshlets.hpp), both clusterings: every triangle in
// exactly one meshlet of one mesh and at most max_triangles; each chart is one orthogonal
// projection (a rotation of the projection onto the meshlet's plane: edge lengths and areas as
// the normal's cosine says), orientation-keeping, injective, inside [0, extent]; NormalCone
// keeps its normal cone; degenerate triangles get harmless meshlets; bad settings name the
// scene. Then the comparison: NormalCone's meshlets fill their blocks better than
// meshoptimizer's (meshlet_stats), on a sphere and on bumpy surfaces.
#include "renderer/surface/msa/meshlets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include "io/surface_io.hpp"
#include "renderer/surface/charts/planar_charts.hpp"
#include "scene/generators.hpp"
#include "surface/chart_test_scenes.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::msa {
namespace {

using test::Tri2;
using test::area2;
using test::orient;
using test::scene_mesh;
using test::scene_of;
using Tri3 = std::array<glm::dvec3, 3>;

constexpr double kPi = 3.14159265358979323846;

bool finite2(const glm::dvec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }

// A height field over [-1, 1]^2 (n x n quads, alternating diagonals): smooth hills of amplitude
// `hills` plus uniform noise of amplitude `noise` at the inner points.
SceneMesh terrain(uint32_t n, double hills, double noise, uint32_t seed) {
  SceneMesh m;
  m.name = "terrain";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i) {
      const double x = -1.0 + 2.0 * i / n, y = -1.0 + 2.0 * j / n;
      double z = hills * (std::sin(3.0 * x) * std::cos(2.0 * y) + 0.5 * std::sin(7.0 * x + 5.0 * y));
      if (i > 0 && j > 0 && i < n && j < n) z += noise * u(rng);
      m.positions.push_back({x, z, y});
    }
  const uint32_t row = n + 1;
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t p = j * row + i;
      if ((i + j) % 2 == 0) {
        m.triangles.push_back({p, p + row, p + row + 1});
        m.triangles.push_back({p, p + row + 1, p + 1});
      } else {
        m.triangles.push_back({p, p + row, p + 1});
        m.triangles.push_back({p + 1, p + row, p + row + 1});
      }
    }
  return m;
}

// An icosphere with every point moved radially by uniform noise of relative amplitude `noise`.
SceneMesh noisy_sphere(uint32_t subdivisions, double noise, uint32_t seed) {
  SceneMesh m = test::sphere_mesh(glm::dvec3(0.0), 1.0, subdivisions, false, 0);
  m.name = "noisy sphere";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto& p : m.positions) p *= 1.0 + noise * u(rng);
  return m;
}

// A helicoid strip (radius 0.3 .. 1, `turns` turns, rising `pitch` per turn): its projection
// onto any plane near z = const wraps around itself, so charts have to refuse overlaps.
SceneMesh helicoid(double turns, double pitch, uint32_t around, uint32_t across) {
  SceneMesh m;
  m.name = "helicoid";
  const uint32_t n_around = static_cast<uint32_t>(std::ceil(turns * around));
  for (uint32_t a = 0; a <= n_around; ++a) {
    const double theta = 2.0 * kPi * turns * a / n_around;
    for (uint32_t r = 0; r <= across; ++r) {
      const double radius = 0.3 + 0.7 * r / across;
      m.positions.push_back({radius * std::cos(theta), radius * std::sin(theta), pitch * theta / (2.0 * kPi)});
    }
  }
  const uint32_t row = across + 1;
  for (uint32_t a = 0; a < n_around; ++a)
    for (uint32_t r = 0; r < across; ++r) {
      const uint32_t p = a * row + r;
      m.triangles.push_back({p, p + 1, p + row + 1});
      m.triangles.push_back({p, p + row + 1, p + row});
    }
  return m;
}

struct Flat {
  std::vector<Tri3> p;
  std::vector<uint32_t> mesh;
};

Flat flatten(const SurfaceScene& scene) {
  Flat f;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m)
    for (const auto& t : scene.meshes[m].triangles) {
      f.p.push_back({scene.meshes[m].positions[t[0]], scene.meshes[m].positions[t[1]], scene.meshes[m].positions[t[2]]});
      f.mesh.push_back(m);
    }
  return f;
}

glm::dvec3 cross_of(const Tri3& p) { return glm::cross(p[1] - p[0], p[2] - p[0]); }

// No plane: |cross| <= 1e-12 (longest edge)^2 or a non-finite corner (the header's rule).
bool degenerate3(const Tri3& p) {
  double longest = 0.0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, glm::dot(p[(k + 1) % 3] - p[k], p[(k + 1) % 3] - p[k]));
  const double len = glm::length(cross_of(p));
  return !(std::isfinite(len) && std::isfinite(longest) && len > 1e-12 * longest);
}

// Interiors of two counter-clockwise triangles overlap by more than `eps` (distance): no edge of
// either has the other in its outer half-plane, up to eps.
bool overlap(const Tri2& a, const Tri2& b, double eps) {
  auto separated = [eps](const Tri2& s, const Tri2& t) {
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 p = s[k], q = s[(k + 1) % 3];
      const double len = glm::length(q - p);
      bool all_out = true;
      for (int v = 0; v < 3 && all_out; ++v) all_out = orient(p, q, t[v]) <= eps * len;
      if (all_out) return true;
    }
    return false;
  };
  return !separated(a, b) && !separated(b, a);
}

struct Checked {
  double worst_rotation = 0.0;   // |A^T A - I| of the fitted chart map
  double worst_fit = 0.0;        // corner distance from the fitted map, relative to the extent
  double worst_area = 0.0;       // |chart area - 3D area cos| / 3D area
  double worst_deviation = 0.0;  // degrees, triangle normal vs meshlet normal
  size_t overlap_tests = 0;
};

// Everything the header promises about a MeshletSet.
void check_set_into(const SurfaceScene& scene, const MeshletSettings& settings, const MeshletSet& set, Checked& c) {
  const Flat flat = flatten(scene);
  const size_t n = flat.p.size();
  EXPECT_EQ(set.meshlet_of_triangle.size(), n);
  EXPECT_EQ(set.corner_chart.size(), n);
  if (set.meshlet_of_triangle.size() != n || set.corner_chart.size() != n) return;
  std::vector<int> seen(n, 0);
  for (uint32_t id = 0; id < set.meshlets.size(); ++id) {
    const Meshlet& m = set.meshlets[id];
    SCOPED_TRACE(scene.name + ", meshlet " + std::to_string(id));
    EXPECT_GE(m.triangles.size(), 1u);
    EXPECT_LE(m.triangles.size(), settings.max_triangles);
    EXPECT_TRUE(finite2(m.extent));
    EXPECT_GE(m.extent.x, m.extent.y);
    EXPECT_GE(m.extent.y, 0.0);
    bool point_like = m.normal == glm::dvec3(0.0);
    for (uint32_t t : m.triangles) {
      ASSERT_LT(t, n);
      ++seen[t];
      EXPECT_EQ(set.meshlet_of_triangle[t], id) << "triangle " << t;
      EXPECT_EQ(flat.mesh[t], m.mesh) << "triangle " << t << " of another mesh";
      for (const auto& q : set.corner_chart[t]) EXPECT_TRUE(finite2(q)) << "triangle " << t;
    }
    if (point_like) {
      // A degenerate triangle's meshlet: alone, corners at 0, extent 0.
      EXPECT_EQ(m.triangles.size(), 1u);
      EXPECT_TRUE(degenerate3(flat.p[m.triangles[0]])) << "a triangle with a plane got a point-like meshlet";
      EXPECT_EQ(m.extent, glm::dvec2(0.0));
      for (const auto& q : set.corner_chart[m.triangles[0]]) EXPECT_EQ(q, glm::dvec2(0.0));
      continue;
    }
    EXPECT_NEAR(glm::length(m.normal), 1.0, 1e-12);
    const double scale = std::max(m.extent.x, std::numeric_limits<double>::min());
    // Corners within [0, extent] and touching all four sides (the rectangle is the bounding box).
    glm::dvec2 lo(1e300), hi(-1e300);
    for (uint32_t t : m.triangles)
      for (const auto& q : set.corner_chart[t]) {
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
      }
    EXPECT_NEAR(lo.x, 0.0, 1e-9 * scale);
    EXPECT_NEAR(lo.y, 0.0, 1e-9 * scale);
    EXPECT_NEAR(hi.x, m.extent.x, 1e-9 * scale);
    EXPECT_NEAR(hi.y, m.extent.y, 1e-9 * scale);
    // One map for the whole meshlet: chart = A proj + b with A a rotation (det +1), proj the
    // orthogonal projection onto the plane of m.normal in a fixed frame (e_u, e_v).
    const glm::dvec3 nrm = m.normal;
    const glm::dvec3 axis = std::abs(nrm.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    const glm::dvec3 e_u = glm::normalize(axis - glm::dot(axis, nrm) * nrm), e_v = glm::cross(nrm, e_u);
    auto proj = [&](const glm::dvec3& p) { return glm::dvec2(glm::dot(p, e_u), glm::dot(p, e_v)); };
    // Fit on the meshlet's largest triangle.
    uint32_t fit = m.triangles[0];
    for (uint32_t t : m.triangles)
      if (glm::length(cross_of(flat.p[t])) > glm::length(cross_of(flat.p[fit]))) fit = t;
    const Tri3& f3 = flat.p[fit];
    const Tri2& f2 = set.corner_chart[fit];
    const glm::dvec2 p1 = proj(f3[1]) - proj(f3[0]), p2 = proj(f3[2]) - proj(f3[0]);
    const glm::dvec2 c1 = f2[1] - f2[0], c2 = f2[2] - f2[0];
    const double det = p1.x * p2.y - p1.y * p2.x;
    ASSERT_GT(std::abs(det), 0.0);
    // A = C P^-1 with P = [p1 p2], C = [c1 c2] (columns).
    const glm::dvec2 a_col0 = (c1 * p2.y - c2 * p1.y) / det, a_col1 = (c2 * p1.x - c1 * p2.x) / det;
    auto apply = [&](const glm::dvec2& q) { return a_col0 * q.x + a_col1 * q.y; };
    const double rot_err = std::max({std::abs(glm::dot(a_col0, a_col0) - 1.0), std::abs(glm::dot(a_col1, a_col1) - 1.0),
                                     std::abs(glm::dot(a_col0, a_col1)), std::abs(a_col0.x * a_col1.y - a_col0.y * a_col1.x - 1.0)});
    c.worst_rotation = std::max(c.worst_rotation, rot_err);
    EXPECT_LT(rot_err, 1e-9) << "the chart is not a rotation of the orthogonal projection";
    const glm::dvec2 offset = f2[0] - apply(proj(f3[0]));
    const double cos_max = std::cos(settings.max_normal_angle_deg * kPi / 180.0);
    for (uint32_t t : m.triangles) {
      const Tri3& p = flat.p[t];
      const Tri2& q = set.corner_chart[t];
      ASSERT_FALSE(degenerate3(p)) << "degenerate triangle " << t << " shares a meshlet";
      for (int v = 0; v < 3; ++v) {
        const double d = glm::length(q[v] - (apply(proj(p[v])) + offset)) / scale;
        c.worst_fit = std::max(c.worst_fit, d);
        EXPECT_LT(d, 1e-9) << "triangle " << t << " corner " << v << " is not on the meshlet's projection";
        // Edge lengths never longer than in 3D.
        const double e3 = glm::length(p[(v + 1) % 3] - p[v]), e2 = glm::length(q[(v + 1) % 3] - q[v]);
        EXPECT_LE(e2, e3 * (1.0 + 1e-9) + 1e-12 * scale) << "triangle " << t;
      }
      // Orientation kept, area scaled by the cosine.
      const glm::dvec3 cr = cross_of(p);
      const double area3 = 0.5 * glm::length(cr);
      const double cosine = glm::dot(cr, nrm) / glm::length(cr);
      EXPECT_GT(area2(q), 0.0) << "triangle " << t << " flipped";
      const double area_err = std::abs(0.5 * area2(q) - area3 * cosine) / area3;
      c.worst_area = std::max(c.worst_area, area_err);
      EXPECT_LT(area_err, 1e-9) << "triangle " << t;
      const double deviation = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / kPi;
      c.worst_deviation = std::max(c.worst_deviation, deviation);
      if (settings.clustering == Clustering::NormalCone) {
        EXPECT_GE(cosine, cos_max - 1e-12) << "triangle " << t << " outside the normal cone";
      }
    }
    if (settings.clustering == Clustering::NormalCone) {
      // The plane is the seed's: the meshlet's lowest triangle.
      const glm::dvec3 seed = glm::normalize(cross_of(flat.p[m.triangles.front()]));
      EXPECT_LT(glm::length(seed - nrm), 1e-12);
    } else {
      glm::dvec3 mean(0.0);
      for (uint32_t t : m.triangles) mean += 0.5 * cross_of(flat.p[t]);
      EXPECT_LT(glm::length(glm::normalize(mean) - nrm), 1e-9) << "not the area-weighted mean normal";
    }
    // Injective: no two triangles' chart images overlap (beyond 1e-9 of the extent).
    for (size_t a = 0; a < m.triangles.size(); ++a)
      for (size_t b = a + 1; b < m.triangles.size(); ++b) {
        ++c.overlap_tests;
        EXPECT_FALSE(overlap(set.corner_chart[m.triangles[a]], set.corner_chart[m.triangles[b]], 1e-9 * scale))
            << "triangles " << m.triangles[a] << " and " << m.triangles[b] << " overlap in their chart";
      }
  }
  for (size_t t = 0; t < n; ++t) EXPECT_EQ(seen[t], 1) << scene.name << ": triangle " << t << " is in " << seen[t] << " meshlets";
}

Checked check_set(const SurfaceScene& scene, const MeshletSettings& settings, const MeshletSet& set) {
  Checked c;
  check_set_into(scene, settings, set, c);
  return c;
}

void expect_finite(const MeshletStats& s) {
  for (double v : {s.mean_triangles, s.mean_normal_deviation_deg, s.chart_fill, s.block_fill}) EXPECT_TRUE(std::isfinite(v));
}

std::string stats_line(const std::string& scene, const char* clustering, double texels_per_unit, const MeshletStats& s) {
  char line[512];
  std::snprintf(line, sizeof line,
                "%-28s %-13s %7.1f tex/unit: %6zu meshlets, %5.1f triangles mean, %3u max, normal deviation %5.2f deg, chart fill "
                "%.3f, block fill %.3f",
                scene.c_str(), clustering, texels_per_unit, s.meshlets, s.mean_triangles, s.max_triangles, s.mean_normal_deviation_deg,
                s.chart_fill, s.block_fill);
  return line;
}

MeshletSettings with(Clustering c) {
  MeshletSettings s;
  s.clustering = c;
  return s;
}

std::vector<SurfaceScene> small_scenes() {
  std::vector<SurfaceScene> out;
  out.push_back(make_cornell_box());
  out.push_back(make_furnace(0.5, 1.0, 1));  // 80 triangles: one meshoptimizer meshlet that cannot chart
  out.push_back(scene_of("sphere and cube", {test::sphere_mesh(glm::dvec3(0.0), 1.0, 3, false, 0),
                                             scene_mesh(make_cube_surface(glm::dvec3(2.5, 0.0, 0.0), 0.8, 3), "cube")}));
  out.push_back(scene_of("helicoid", {helicoid(2.5, 0.05, 48, 4)}));
  out.push_back(scene_of("noisy terrain", {terrain(24, 0.15, 0.05, 7)}));
  out.push_back(scene_of("noisy sphere", {noisy_sphere(3, 0.08, 11)}));
  return out;
}

TEST(Meshlets, EveryClusteringKeepsTheHeadersPromises) {
  for (Clustering clustering : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
    for (uint32_t max_triangles : {84u, 126u, 7u, 1u}) {
      for (const SurfaceScene& scene : small_scenes()) {
        MeshletSettings s = with(clustering);
        s.max_triangles = max_triangles;
        SCOPED_TRACE(std::string(clustering == Clustering::NormalCone ? "NormalCone" : "Meshoptimizer") + ", max " + std::to_string(max_triangles));
        const MeshletSet set = build_meshlets(scene, s);
        const Checked c = check_set(scene, s, set);
        if (max_triangles == 84)
          std::printf("%-16s %-13s %5zu meshlets: worst rotation %.1e, fit %.1e, area %.1e, deviation %.1f deg, %zu overlap tests\n",
                      scene.name.c_str(), clustering == Clustering::NormalCone ? "NormalCone" : "Meshoptimizer", set.meshlets.size(),
                      c.worst_rotation, c.worst_fit, c.worst_area, c.worst_deviation, c.overlap_tests);
        if (max_triangles == 1) {
          EXPECT_EQ(set.meshlets.size(), set.corner_chart.size());
        }
        expect_finite(meshlet_stats(scene, set, 64.0));
      }
    }
  }
}

TEST(Meshlets, NormalConeAngleBoundsTheDeviation) {
  const SurfaceScene scene = scene_of("noisy sphere", {noisy_sphere(3, 0.1, 5)});
  for (double angle : {10.0, 30.0, 60.0, 89.0}) {
    MeshletSettings s = with(Clustering::NormalCone);
    s.max_normal_angle_deg = angle;
    const MeshletSet set = build_meshlets(scene, s);
    const Checked c = check_set(scene, s, set);
    EXPECT_LE(c.worst_deviation, angle + 1e-9);
  }
}

// A flat square of two triangles: one meshlet, exactly its 3 x 1 rectangle, in both clusterings.
TEST(Meshlets, FlatRectangleIsItsOwnChart) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const glm::dvec3 a = glm::normalize(glm::cross(n, glm::dvec3(0, 0, 1))), b = glm::cross(n, a);
  SceneMesh m;
  m.name = "rectangle";
  const glm::dvec3 o(0.2, 0.4, -0.1);
  m.positions = {o, o + 3.0 * a, o + 3.0 * a + b, o + b};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const SurfaceScene scene = scene_of("rectangle", {m});
  for (Clustering clustering : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
    const MeshletSet set = build_meshlets(scene, with(clustering));
    ASSERT_EQ(set.meshlets.size(), 1u);
    EXPECT_NEAR(set.meshlets[0].extent.x, 3.0, 1e-12);
    EXPECT_NEAR(set.meshlets[0].extent.y, 1.0, 1e-12);
    // At 9.9 texels per unit: ceil(29.7) + 2 = 32 by ceil(9.9) + 2 = 12 -> a 32 x 16 block
    // (whose scale, min(30 / 3, 14 / 1) = 10, exceeds 9.9), 3 * 9.9^2 of 512 texels covered.
    const MeshletStats st = meshlet_stats(scene, set, 9.9);
    EXPECT_NEAR(st.chart_fill, 1.0, 1e-12);
    EXPECT_NEAR(st.block_fill, 3.0 * 9.9 * 9.9 / 512.0, 1e-12);
    EXPECT_EQ(st.meshlets, 1u);
    EXPECT_EQ(st.max_triangles, 2u);
    EXPECT_NEAR(st.mean_normal_deviation_deg, 0.0, 1e-6);
    // At 1000 texels per unit the 256-texel side clamps: the block holds 254 / 3 texels per unit.
    const MeshletStats big = meshlet_stats(scene, set, 1000.0);
    EXPECT_NEAR(big.block_fill, 3.0 * (254.0 / 3.0) * (254.0 / 3.0) / (256.0 * 256.0), 1e-12);
  }
}

TEST(Meshlets, BlockClassesFollowTheRule) {
  // w = smallest power of two >= ceil(extent.x * density) + 2, in [8, 256].
  EXPECT_EQ(msa_class_size(msa_class_for({0.0, 0.0}, 5.0)), glm::uvec2(8, 8));
  EXPECT_EQ(msa_class_size(msa_class_for({3.0, 1.0}, 10.0)), glm::uvec2(32, 16));
  EXPECT_EQ(msa_class_size(msa_class_for({3.0, 1.0}, 10.1)), glm::uvec2(64, 16));  // ceil(30.3) + 2 = 33
  EXPECT_EQ(msa_class_size(msa_class_for({1e6, 1e6}, 1.0)), glm::uvec2(256, 256));
  EXPECT_EQ(msa_class_for({1.0, 0.1}, 60.0), 3u * 6u + 0u);  // 62 -> 64, 8 -> 8
  EXPECT_NEAR(msa_block_scale({3.0, 1.0}, msa_class_for({3.0, 1.0}, 10.0)), 10.0, 1e-12);  // min(30 / 3, 14 / 1)
  EXPECT_EQ(msa_block_scale({0.0, 0.0}, 0), 1.0);
}

// ---- Meshoptimizer: its meshlets, split only where they do not chart ------------------------------

// meshopt_buildMeshlets called directly on one mesh (64 vertices, 84 triangles, cone weight 0.5):
// each meshlet's triangle ids in meshoptimizer's order (the mesh has no repeated vertex triples).
std::vector<std::vector<uint32_t>> direct_meshoptimizer(const SceneMesh& mesh) {
  std::vector<uint32_t> indices;
  for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
  std::vector<float> positions;
  for (const auto& p : mesh.positions)
    for (int c = 0; c < 3; ++c) positions.push_back(static_cast<float>(p[c]));
  const size_t bound = meshopt_buildMeshletsBound(indices.size(), 64, 84);
  std::vector<meshopt_Meshlet> meshlets(bound);
  std::vector<unsigned int> vertices(bound * 64);
  std::vector<unsigned char> triangles(bound * 84 * 3);
  const size_t count = meshopt_buildMeshlets(meshlets.data(), vertices.data(), triangles.data(), indices.data(), indices.size(),
                                             positions.data(), mesh.positions.size(), 12, 64, 84, 0.5f);
  std::map<std::array<uint32_t, 3>, uint32_t> id;
  for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    auto key = mesh.triangles[t];
    std::sort(key.begin(), key.end());
    id[key] = t;
  }
  std::vector<std::vector<uint32_t>> out(count);
  for (size_t m = 0; m < count; ++m)
    for (uint32_t t = 0; t < meshlets[m].triangle_count; ++t) {
      std::array<uint32_t, 3> key;
      for (int c = 0; c < 3; ++c) key[c] = vertices[meshlets[m].vertex_offset + triangles[meshlets[m].triangle_offset + 3 * t + c]];
      std::sort(key.begin(), key.end());
      out[m].push_back(id.at(key));
    }
  return out;
}

std::vector<std::vector<uint32_t>> sorted_groups(std::vector<std::vector<uint32_t>> groups) {
  for (auto& g : groups) std::sort(g.begin(), g.end());
  std::sort(groups.begin(), groups.end());
  return groups;
}

// On a flat surface every meshoptimizer meshlet charts: the meshlets are exactly meshoptimizer's.
TEST(Meshlets, FlatSurfaceKeepsMeshoptimizersMeshlets) {
  const SurfaceScene scene = scene_of("flat grid", {terrain(32, 0.0, 0.0, 1)});
  const MeshletSet set = build_meshlets(scene, with(Clustering::Meshoptimizer));
  std::vector<std::vector<uint32_t>> ours;
  for (const Meshlet& m : set.meshlets) ours.push_back(m.triangles);
  const auto theirs = direct_meshoptimizer(scene.meshes[0]);
  EXPECT_GT(theirs.size(), 2048u / 84u);
  EXPECT_EQ(sorted_groups(ours), sorted_groups(theirs));
}

// A closed 80-triangle sphere is one meshoptimizer meshlet, which no plane charts: it is split
// in halves of meshoptimizer's order until each half charts.
TEST(Meshlets, MeshletsThatDoNotChartAreSplitInHalves) {
  const SurfaceScene scene = make_furnace(0.5, 1.0, 1);
  const auto theirs = direct_meshoptimizer(scene.meshes[0]);
  ASSERT_EQ(theirs.size(), 1u);
  ASSERT_EQ(theirs[0].size(), 80u);
  const MeshletSet set = build_meshlets(scene, with(Clustering::Meshoptimizer));
  check_set(scene, with(Clustering::Meshoptimizer), set);
  EXPECT_GE(set.meshlets.size(), 2u);
  // Each meshlet is a range [k n / 2^d, (k + 1) n / 2^d) of meshoptimizer's order (halves by
  // integer division: sizes n >> d or (n >> d) + 1).
  std::vector<uint32_t> position(80);
  for (uint32_t i = 0; i < 80; ++i) position[theirs[0][i]] = i;
  for (const Meshlet& m : set.meshlets) {
    std::vector<uint32_t> at;
    for (uint32_t t : m.triangles) at.push_back(position[t]);
    std::sort(at.begin(), at.end());
    EXPECT_EQ(at.back() - at.front() + 1, at.size()) << "not a contiguous range of meshoptimizer's order";
    bool half = false;
    for (uint32_t d = 1; d < 8; ++d) half = half || at.size() == (80u >> d) || at.size() == (80u >> d) + 1;
    EXPECT_TRUE(half) << at.size() << " triangles";
  }
}

// chart_triangles (planar_charts.hpp), which the splitting relies on: nullopt for what no plane
// charts, a chart otherwise.
TEST(Meshlets, ChartTrianglesRefusesWhatCannotChart) {
  SceneMesh m;
  m.name = "pieces";
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 0, 0}, {3, 0, 0}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}, {0, 2, 1}, {0, 1, 2}, {1, 4, 5}};
  const SurfaceScene scene = scene_of("pieces", {m, m});  // triangles 0..4 and 5..9
  const auto geometry = charts::triangle_geometry(scene);
  const auto square = charts::chart_triangles(geometry, {1, 0});
  ASSERT_TRUE(square.has_value());
  EXPECT_EQ(square->triangles, (std::vector<uint32_t>{0, 1}));
  EXPECT_NEAR(square->extent.x, 1.0, 1e-15);
  EXPECT_NEAR(square->extent.y, 1.0, 1e-15);
  EXPECT_FALSE(charts::chart_triangles(geometry, {}).has_value());
  EXPECT_FALSE(charts::chart_triangles(geometry, {0, 2}).has_value());   // turned over: flips
  EXPECT_FALSE(charts::chart_triangles(geometry, {0, 3}).has_value());   // duplicates: overlap
  EXPECT_FALSE(charts::chart_triangles(geometry, {0, 0}).has_value());   // a repeated id
  EXPECT_FALSE(charts::chart_triangles(geometry, {0, 6}).has_value());   // two meshes
  EXPECT_FALSE(charts::chart_triangles(geometry, {0, 4}).has_value());   // with a degenerate triangle
  const auto point = charts::chart_triangles(geometry, {4});             // a degenerate triangle alone
  ASSERT_TRUE(point.has_value());
  EXPECT_TRUE(point->point_like());
  EXPECT_EQ(point->extent, glm::dvec2(0.0));
  EXPECT_FALSE(charts::chart_triangles(geometry, {10}).has_value());     // no such triangle
}

// ---- Degenerate triangles and bad input -------------------------------------------------------

TEST(Meshlets, DegenerateTrianglesGetHarmlessMeshletsOfTheirOwn) {
  SceneMesh m = scene_mesh(make_cube_surface(glm::dvec3(0.0), 1.0, 2), "cube with slivers");
  const uint32_t base = static_cast<uint32_t>(m.positions.size());
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  m.positions.push_back({3.0, 0.0, 0.0});
  m.positions.push_back({4.0, 0.0, 0.0});
  m.positions.push_back({5.0, 0.0, 0.0});    // collinear with the two before
  m.positions.push_back({4.0, 1e-30, 0.0});  // an area of ~1e-30
  m.positions.push_back({nan, 0.0, 1.0});
  m.positions.push_back({inf, 1.0, 0.0});
  const uint32_t first_degenerate = static_cast<uint32_t>(m.triangles.size());
  m.triangles.push_back({base, base + 1, base + 2});      // collinear
  m.triangles.push_back({base, base, base + 1});          // repeated vertex
  m.triangles.push_back({base + 1, base + 1, base + 1});  // a point
  m.triangles.push_back({base, base + 2, base + 3});      // near-zero area
  m.triangles.push_back({base, base + 1, base + 4});      // NaN corner
  m.triangles.push_back({base, base + 5, base + 1});      // infinite corner
  const uint32_t degenerate_count = 6;
  m.triangles.push_back(m.triangles[0]);                  // a duplicate of a cube triangle
  m.triangles.push_back({m.triangles[1][0], m.triangles[1][2], m.triangles[1][1]});  // a cube triangle turned over
  const SurfaceScene scene = scene_of("slivers", {m, scene_mesh(make_icosphere(glm::dvec3(4.0), 0.5, 1), "sphere")});
  for (Clustering clustering : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
    const MeshletSettings s = with(clustering);
    const MeshletSet set = build_meshlets(scene, s);
    check_set(scene, s, set);
    for (uint32_t t = first_degenerate; t < first_degenerate + degenerate_count; ++t) {
      const Meshlet& own = set.meshlets[set.meshlet_of_triangle[t]];
      EXPECT_EQ(own.triangles, std::vector<uint32_t>{t});
      EXPECT_EQ(own.extent, glm::dvec2(0.0));
      for (const auto& q : set.corner_chart[t]) EXPECT_EQ(q, glm::dvec2(0.0));
    }
    // The duplicate overlaps its twin exactly: never in the same meshlet.
    EXPECT_NE(set.meshlet_of_triangle[0], set.meshlet_of_triangle[first_degenerate + degenerate_count]);
    const MeshletStats st = meshlet_stats(scene, set, 16.0);
    expect_finite(st);
    EXPECT_GT(st.block_fill, 0.0);
  }
}

TEST(Meshlets, EmptySceneHasNoMeshlets) {
  for (Clustering clustering : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
    const SurfaceScene scene = scene_of("empty", {SceneMesh{}});
    const MeshletSet set = build_meshlets(scene, with(clustering));
    EXPECT_TRUE(set.meshlets.empty());
    EXPECT_TRUE(set.corner_chart.empty());
    const MeshletStats st = meshlet_stats(scene, set, 8.0);
    EXPECT_EQ(st.meshlets, 0u);
    expect_finite(st);
  }
}

TEST(Meshlets, BadInputNamesTheScene) {
  const SurfaceScene scene = make_furnace(0.5, 1.0, 1);
  auto fails = [&](const MeshletSettings& s, const std::string& words) {
    test::expect_input_error([&] { (void)build_meshlets(scene, s); }, scene.name, words);
  };
  for (Clustering clustering : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
    MeshletSettings s = with(clustering);
    for (uint32_t max : {0u, 127u, 1000u}) {
      s.max_triangles = max;
      fails(s, "triangles per meshlet");
    }
    s = with(clustering);
    for (double angle : {0.0, 90.0, -10.0, 120.0, std::numeric_limits<double>::quiet_NaN()}) {
      s.max_normal_angle_deg = angle;
      fails(s, "angle");
    }
    s = with(clustering);
    for (double weight : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
      s.cone_weight = weight;
      fails(s, "cone weight");
    }
  }
  SurfaceScene broken = scene_of("broken", {scene_mesh(make_icosphere(glm::dvec3(0.0), 1.0, 1), "sphere")});
  broken.meshes[0].triangles.push_back({0, 1, 999});
  try {
    (void)build_meshlets(broken, {});
    ADD_FAILURE() << "no error for a vertex index out of range";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "broken");
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  const MeshletSet set = build_meshlets(scene, {});
  EXPECT_THROW((void)meshlet_stats(scene, set, 0.0), InputError);
  EXPECT_THROW((void)meshlet_stats(scene, set, std::numeric_limits<double>::infinity()), InputError);
  EXPECT_THROW((void)meshlet_stats(make_cornell_box(), set, 8.0), InputError);
}

// ---- The comparison: NormalCone against meshoptimizer ------------------------------------------

struct Compared {
  MeshletStats cone, meshopt;
};

Compared compare(const SurfaceScene& scene, double texels_per_unit, bool check) {
  Compared out;
  for (Clustering clustering : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
    const MeshletSettings s = with(clustering);
    const MeshletSet set = build_meshlets(scene, s);
    if (check) check_set(scene, s, set);
    const MeshletStats st = meshlet_stats(scene, set, texels_per_unit);
    expect_finite(st);
    const bool cone = clustering == Clustering::NormalCone;
    std::printf("%s\n", stats_line(scene.name, cone ? "NormalCone" : "Meshoptimizer", texels_per_unit, st).c_str());
    (cone ? out.cone : out.meshopt) = st;
  }
  return out;
}

// Texel densities at which a meshlet's block is about 16, 32 and 64 texels wide: the mean edge
// length e, 84 triangles ~ a patch of sqrt(84 * e^2 sqrt(3) / 4) ~ 6 e across.
std::vector<double> densities(const SurfaceScene& scene) {
  const Flat flat = flatten(scene);
  double sum = 0.0;
  for (const auto& p : flat.p) sum += glm::length(p[1] - p[0]) + glm::length(p[2] - p[1]) + glm::length(p[0] - p[2]);
  const double edge = sum / (3.0 * double(flat.p.size()));
  return {14.0 / (6.0 * edge), 30.0 / (6.0 * edge), 62.0 / (6.0 * edge)};
}

// NormalCone's charts fill their rectangles better everywhere, and their blocks better at every
// density but one: on the noisy terrain (slopes up to ~1.3 from the noise alone) the 60-degree
// cone cuts meshlets to 15 triangles on average, and at the coarsest density (blocks ~16 texels)
// the border texel and the 8-texel minimum make that cost as much as NormalCone's tighter
// rectangles save (block fill 0.149 against meshoptimizer's 0.150 when written): there only the
// chart fill is asserted.
TEST(Meshlets, NormalConeFillsBlocksBetterThanMeshoptimizer) {
  struct Case {
    SurfaceScene scene;
    bool coarsest_block_win;
  };
  std::vector<Case> cases;
  cases.push_back({scene_of("sphere (5120 triangles)", {test::sphere_mesh(glm::dvec3(0.0), 1.0, 4, false, 0)}), true});
  cases.push_back({scene_of("sphere (20480 triangles)", {test::sphere_mesh(glm::dvec3(0.0), 1.0, 5, false, 0)}), true});
  cases.push_back({scene_of("noisy sphere (5120)", {noisy_sphere(4, 0.02, 3)}), true});
  cases.push_back({scene_of("bumpy terrain (8192)", {terrain(64, 0.2, 0.0, 1)}), true});
  cases.push_back({scene_of("noisy terrain (8192)", {terrain(64, 0.2, 0.02, 2)}), false});
  for (const Case& k : cases) {
    SCOPED_TRACE(k.scene.name);
    const std::vector<double> rhos = densities(k.scene);
    for (size_t i = 0; i < rhos.size(); ++i) {
      const Compared c = compare(k.scene, rhos[i], i == 0);
      EXPECT_GT(c.cone.chart_fill, c.meshopt.chart_fill) << "at " << rhos[i] << " texels per unit";
      if (i > 0 || k.coarsest_block_win) {
        EXPECT_GT(c.cone.block_fill, c.meshopt.block_fill) << "at " << rhos[i] << " texels per unit";
      }
    }
  }
}

// The real meshes of datasets/ (when the cache holds them): stats only, nothing asserted beyond
// finite numbers. The cache is where datasets/fetch-real.sh puts it: $PRISMOID_DATA_CACHE, else
// datasets/.cache of this source tree.
std::filesystem::path real_mesh_dir() {
  const char* cache = std::getenv("PRISMOID_DATA_CACHE");
  const std::filesystem::path root = cache != nullptr && *cache != '\0' ? std::filesystem::path(cache)
                                                                         : std::filesystem::path(PRISMOID_SOURCE_DIR) / "datasets" / ".cache";
  return root / "meshes";
}

TEST(Meshlets, RealMeshesStats) {
  const std::filesystem::path dir = real_mesh_dir();
  int found = 0;
  for (const char* name : {"bunny00", "armadillo", "ChineseDragon-10kv"}) {
    const std::filesystem::path path = dir / (std::string(name) + ".off");
    if (!std::filesystem::exists(path)) {
      std::printf("%s: not in the datasets cache, skipped\n", path.c_str());
      continue;
    }
    ++found;
    const SurfaceScene scene = make_surface_scene(io::read_surface(path.string()));
    SurfaceScene named = scene;
    named.name = name;
    for (double rho : densities(named)) compare(named, rho, false);
    // Conformal charts against projected ones: the sampling of the worst triangle never drops.
    for (Clustering c : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
      MeshletSettings s = with(c);
      const MeshletStats p = meshlet_stats(named, build_meshlets(named, s), densities(named)[1]);
      s.parametrization = Parametrization::Conformal;
      const MeshletSet set = build_meshlets(named, s);
      const MeshletStats q = meshlet_stats(named, set, densities(named)[1]);
      EXPECT_GE(q.sampling_min, p.sampling_min * (1.0 - 1e-9)) << name;
      std::printf("%-20s %-13s charts: sampling min/mean %.3f/%.3f projected, %.3f/%.3f conformal (%zu of %zu meshlets kept their "
                  "projection); block fill %.3f / %.3f\n",
                  name, c == Clustering::NormalCone ? "NormalCone" : "Meshoptimizer", p.sampling_min, p.sampling_mean, q.sampling_min, q.sampling_mean,
                  set.conformal_fallbacks, set.meshlets.size(), p.block_fill, q.block_fill);
    }
  }
  if (found == 0) GTEST_SKIP() << "no real meshes in " << dir << " (stats only)";
}

// ---- Conformal charts (charts::conformal_chart, Parametrization::Conformal) ------------------

// A quarter-turn strip of a cylinder (radius 1, height 1), `around` x `up` quads: each quad is a
// flat rectangle, so the strip unrolls onto the plane without stretching.
SceneMesh cylinder_strip(double degrees, uint32_t around, uint32_t up) {
  SceneMesh m;
  m.name = "cylinder strip";
  for (uint32_t j = 0; j <= up; ++j)
    for (uint32_t i = 0; i <= around; ++i) {
      const double a = degrees * kPi / 180.0 * i / around;
      m.positions.push_back({std::cos(a), std::sin(a), double(j) / up});
    }
  const uint32_t row = around + 1;
  for (uint32_t j = 0; j < up; ++j)
    for (uint32_t i = 0; i < around; ++i) {
      const uint32_t p = j * row + i;
      m.triangles.push_back({p, p + 1, p + row + 1});  // facing the axis' outside
      m.triangles.push_back({p, p + row + 1, p + row});
    }
  return m;
}

// Every triangle's chart edges against its surface edges: the largest |ratio - 1|.
double worst_edge_stretch(const SurfaceScene& scene, const MeshletSet& set) {
  const Flat flat = flatten(scene);
  double worst = 0.0;
  for (size_t t = 0; t < flat.p.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const double surface = glm::length(flat.p[t][(k + 1) % 3] - flat.p[t][k]);
      const double chart = glm::length(set.corner_chart[t][(k + 1) % 3] - set.corner_chart[t][k]);
      worst = std::max(worst, std::abs(chart / surface - 1.0));
    }
  return worst;
}

// Each meshlet's chart: every triangle counter-clockwise, inside [0, extent], and no two
// triangles' interiors overlapping (a separating edge for every pair whose boxes meet).
void expect_injective_charts(const SurfaceScene& scene, const MeshletSet& set) {
  for (uint32_t id = 0; id < set.meshlets.size(); ++id) {
    const Meshlet& m = set.meshlets[id];
    if (m.normal == glm::dvec3(0.0)) continue;
    const double scale = std::max(m.extent.x, 1e-300);
    for (size_t a = 0; a < m.triangles.size(); ++a) {
      const auto& p = set.corner_chart[m.triangles[a]];
      const glm::dvec2 e1 = p[1] - p[0], e2 = p[2] - p[0];
      EXPECT_GT(e1.x * e2.y - e1.y * e2.x, 0.0) << scene.name << ", meshlet " << id << ": a flipped triangle";
      for (const auto& q : p) {
        EXPECT_GE(q.x, -1e-9 * scale);
        EXPECT_GE(q.y, -1e-9 * scale);
        EXPECT_LE(q.x, m.extent.x + 1e-9 * scale);
        EXPECT_LE(q.y, m.extent.y + 1e-9 * scale);
      }
      for (size_t b = a + 1; b < m.triangles.size(); ++b) {
        const auto& r = set.corner_chart[m.triangles[b]];
        auto separated = [scale](const Tri2& x, const Tri2& y) {
          for (int k = 0; k < 3; ++k) {
            const glm::dvec2 o = x[k], d = x[(k + 1) % 3] - x[k];
            bool all = true;
            for (const auto& q : y) all = all && d.x * (q.y - o.y) - d.y * (q.x - o.x) <= 1e-12 * scale * scale;
            if (all) return true;
          }
          return false;
        };
        EXPECT_TRUE(separated(p, r) || separated(r, p)) << scene.name << ", meshlet " << id << ": triangles overlap";
      }
    }
  }
}

// A flat patch has an exact conformal map, its projection: the conformal chart keeps every edge
// (the area normalization gives scale 1), as the projection does.
TEST(ConformalCharts, AFlatPatchKeepsEveryEdge) {
  SceneMesh plane = terrain(12, 0.0, 0.0, 3);
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.2, -0.4, 0.9));
  const glm::dvec3 a = glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0))), b = glm::cross(n, a);
  for (auto& p : plane.positions) p = glm::dvec3(3.0, -1.0, 2.0) + p.x * a + p.z * b;  // terrain is flat in x, z: a tilted plane
  const SurfaceScene scene = scene_of("tilted plane", {plane});
  for (Clustering c : {Clustering::NormalCone, Clustering::Meshoptimizer}) {
    MeshletSettings s = with(c);
    s.parametrization = Parametrization::Conformal;
    const MeshletSet set = build_meshlets(scene, s);
    EXPECT_EQ(set.conformal_fallbacks, 0u);
    EXPECT_LT(worst_edge_stretch(scene, set), 1e-9);
    expect_injective_charts(scene, set);
  }
}

// An 80-degree strip of a cylinder in one meshlet: the projection onto the seed's plane narrows
// the far quads to the cosine of their turn (sampling, the square root of the area ratio, down
// to about 0.5); the conformal chart unrolls the strip, every edge kept (to the solver's
// rounding).
TEST(ConformalCharts, ACylinderStripUnrollsWithoutStretching) {
  const SurfaceScene scene = scene_of("cylinder strip", {cylinder_strip(80.0, 15, 4)});
  MeshletSettings s = with(Clustering::NormalCone);
  s.max_normal_angle_deg = 89.0;
  s.max_triangles = 126;
  const MeshletSet projected = build_meshlets(scene, s);
  ASSERT_EQ(projected.meshlets.size(), 1u);
  s.parametrization = Parametrization::Conformal;
  const MeshletSet conformal = build_meshlets(scene, s);
  ASSERT_EQ(conformal.meshlets.size(), 1u);
  EXPECT_EQ(conformal.conformal_fallbacks, 0u);
  const double stretch = worst_edge_stretch(scene, conformal);
  EXPECT_LT(stretch, 1e-8);
  EXPECT_GT(worst_edge_stretch(scene, projected), 0.5);
  const MeshletStats p = meshlet_stats(scene, projected, 16.0), q = meshlet_stats(scene, conformal, 16.0);
  EXPECT_NEAR(q.sampling_min, 1.0, 1e-8);
  EXPECT_NEAR(q.sampling_mean, 1.0, 1e-8);
  EXPECT_LT(p.sampling_min, 0.6);
  expect_injective_charts(scene, conformal);
  std::printf("cylinder strip: edge stretch %.1e conformal, %.2f projected; sampling min/mean %.3f/%.3f projected, %.3f/%.3f conformal\n",
              stretch, worst_edge_stretch(scene, projected), p.sampling_min, p.sampling_mean, q.sampling_min, q.sampling_mean);
}

// The smallest sampling (square root of chart over surface area) among a meshlet's triangles.
double worst_sampling(const SurfaceScene& scene, const MeshletSet& set, const Meshlet& m) {
  const Flat flat = flatten(scene);
  double worst = 1e300;
  for (uint32_t t : m.triangles) {
    const auto& c = set.corner_chart[t];
    const glm::dvec2 u = c[1] - c[0], v = c[2] - c[0];
    worst = std::min(worst, std::sqrt(std::abs(u.x * v.y - u.y * v.x) / glm::length(cross_of(flat.p[t]))));
  }
  return worst;
}

// On curved and noisy meshes every conformal chart is injective, and no meshlet's worst
// triangle is sampled less densely than under the projection (a meshlet whose conformal chart
// would be keeps its projection, counted); the statistics are printed for the record.
TEST(ConformalCharts, ChartsOfCurvedMeshesAreInjectiveAndNoWorseSampled) {
  for (Clustering c : {Clustering::NormalCone, Clustering::Meshoptimizer})
    for (const SurfaceScene& scene : small_scenes()) {
      MeshletSettings s = with(c);
      const MeshletSet projected = build_meshlets(scene, s);
      const MeshletStats p = meshlet_stats(scene, projected, 64.0);
      s.parametrization = Parametrization::Conformal;
      const MeshletSet set = build_meshlets(scene, s);
      expect_injective_charts(scene, set);
      const MeshletStats q = meshlet_stats(scene, set, 64.0);
      expect_finite(q);
      ASSERT_EQ(set.meshlets.size(), projected.meshlets.size());
      size_t changed = 0;
      for (size_t id = 0; id < set.meshlets.size(); ++id) {
        if (set.meshlets[id].normal == glm::dvec3(0.0) || set.meshlets[id].triangles.size() < 2) continue;
        const double before = worst_sampling(scene, projected, projected.meshlets[id]), after = worst_sampling(scene, set, set.meshlets[id]);
        EXPECT_GE(after, before * (1.0 - 1e-9)) << scene.name << ", meshlet " << id;
        changed += after != before;
      }
      EXPECT_GT(changed, 0u) << scene.name;
      std::printf("%-16s %-13s %5zu meshlets, %3zu kept their projection: sampling min/mean %.3f/%.3f projected, %.3f/%.3f conformal; "
                  "block fill %.3f / %.3f\n",
                  scene.name.c_str(), c == Clustering::NormalCone ? "NormalCone" : "Meshoptimizer", set.meshlets.size(), set.conformal_fallbacks,
                  p.sampling_min, p.sampling_mean, q.sampling_min, q.sampling_mean, p.block_fill, q.block_fill);
    }
}

}  // namespace
}  // namespace prismoid::msa
