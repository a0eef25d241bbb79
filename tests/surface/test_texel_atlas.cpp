// The texel shading atlas (renderer/surface/texel/texel_atlas.hpp): charts are injective similarities
// of the surface (up to the projection's cosine), packed rectangles are disjoint and aligned,
// the triangle index textures match a brute-force evaluation of their rule, and the lookup
// (level selection, bilinear taps, texel barycentrics) does what its definition says.
#include "renderer/surface/texel/texel_atlas.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/generators.hpp"
#include "surface/chart_test_scenes.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "support/test_meshes.hpp"

namespace prismoid::texel {
namespace {

using test::Tri2;
using test::area2;
using test::orient;
using test::scene_mesh;
using test::scene_of;


// A helicoid strip (radius 0.3 .. 1, `turns` turns, rising `pitch` per turn): its projection onto
// any plane near z = const wraps around itself, so chart growing has to refuse overlaps.
SceneMesh helicoid(double turns, double pitch, uint32_t around, uint32_t across) {
  SceneMesh m;
  m.name = "helicoid";
  const uint32_t n_around = static_cast<uint32_t>(std::ceil(turns * around));
  for (uint32_t a = 0; a <= n_around; ++a) {
    const double theta = 6.283185307179586 * turns * a / n_around;
    for (uint32_t r = 0; r <= across; ++r) {
      const double radius = 0.3 + 0.7 * r / across;
      m.positions.push_back({radius * std::cos(theta), radius * std::sin(theta), pitch * theta / 6.283185307179586});
    }
  }
  const uint32_t row = across + 1;
  for (uint32_t a = 0; a < n_around; ++a) {
    for (uint32_t r = 0; r < across; ++r) {
      const uint32_t p = a * row + r;
      m.triangles.push_back({p, p + 1, p + row + 1});
      m.triangles.push_back({p, p + row + 1, p + row});
    }
  }
  return m;
}

// Four flaps on one edge (a non-manifold "book"): two nearly coplanar ones on the same side,
// whose projections overlap, one on the other side, one steep.
SceneMesh book() {
  SceneMesh m;
  m.name = "book";
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.4, 1, 0.1}, {0.5, -1, 0.05}, {0.5, 0.2, 1}};
  m.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 0, 4}, {0, 1, 5}};
  return m;
}

struct NamedScene {
  SurfaceScene scene;
  AtlasSettings settings;
};

std::vector<NamedScene> small_scenes() {
  std::vector<NamedScene> out;
  AtlasSettings s;
  s.target_texels = double(1 << 15);
  out.push_back({make_cornell_box(), s});
  out.push_back({make_furnace(0.5, 1.0, 2), s});
  out.push_back({scene_of("sphere and cube", {scene_mesh(make_icosphere(glm::dvec3(0.0), 1.0, 2), "sphere"),
                                              scene_mesh(make_cube_surface(glm::dvec3(2.5, 0.0, 0.0), 0.8, 3), "cube")}),
                 s});
  out.push_back({scene_of("bulged disk", {scene_mesh(test::make_disk(8, 0.8), "disk")}), s});
  AtlasSettings helix = s;
  helix.levels = 3;
  helix.max_chart_triangles = 4096;
  out.push_back({scene_of("helicoid", {helicoid(2.5, 0.1, 48, 4)}), helix});
  out.push_back({scene_of("non-manifold book", {book()}), s});
  AtlasSettings one = s;
  one.levels = 1;
  one.max_chart_triangles = 7;
  out.push_back({scene_of("sphere, 1 level, 7 per chart", {scene_mesh(make_icosphere(glm::dvec3(0.0), 1.0, 2), "sphere")}), one});
  return out;
}

struct Flat {
  std::vector<std::array<glm::dvec3, 3>> p;
};

Flat flatten(const SurfaceScene& scene) {
  Flat f;
  for (const auto& m : scene.meshes)
    for (const auto& t : m.triangles) f.p.push_back({m.positions[t[0]], m.positions[t[1]], m.positions[t[2]]});
  return f;
}

glm::dvec3 normal_of(const std::array<glm::dvec3, 3>& p) { return glm::cross(p[1] - p[0], p[2] - p[0]); }

// The atlas's rule for a triangle without a plane: |cross| <= 1e-12 (longest edge)^2.
bool degenerate3(const std::array<glm::dvec3, 3>& p) {
  double longest = 0.0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, glm::dot(p[(k + 1) % 3] - p[k], p[(k + 1) % 3] - p[k]));
  return !(glm::length(normal_of(p)) > 1e-12 * longest);
}

TEST(TexelAtlas, NonManifoldEdgeJoinsOnlyWhatFits) {
  AtlasSettings s;
  s.target_texels = 4096.0;
  const TexelAtlas atlas = build_texel_atlas(scene_of("book", {book()}), s);
  // 0 and 2 (the far side, unfolded into the plane) fit together; 1 overlaps 0; 3 is 80 degrees off.
  EXPECT_EQ(atlas.chart_of_triangle[0], atlas.chart_of_triangle[2]);
  EXPECT_NE(atlas.chart_of_triangle[0], atlas.chart_of_triangle[1]);
  EXPECT_NE(atlas.chart_of_triangle[0], atlas.chart_of_triangle[3]);
  EXPECT_NE(atlas.chart_of_triangle[1], atlas.chart_of_triangle[3]);
}

void print_summary(const std::string& name, const TexelAtlas& atlas, double seconds) {
  size_t most = 0, total = 0;
  for (const auto& c : atlas.charts) {
    most = std::max(most, c.triangles.size());
    total += c.triangles.size();
  }
  const double covered = double(atlas.covered_texels_level0()) / (double(atlas.width) * atlas.height);
  const double used = double(atlas.used_texels()) / double(atlas.texel_count());
  std::printf("[texel atlas] %-32s %7zu triangles, %6zu charts, triangles per chart mean %.1f max %zu, level 0 %u x %u, "
              "covered %.3f of level 0, used %.3f of all levels, built in %.3f s\n",
              name.c_str(), total, atlas.charts.size(), double(total) / double(std::max<size_t>(atlas.charts.size(), 1)), most,
              atlas.width, atlas.height, covered, used, seconds);
}

TexelAtlas timed_build(const SurfaceScene& scene, const AtlasSettings& settings) {
  const auto t0 = std::chrono::steady_clock::now();
  TexelAtlas atlas = build_texel_atlas(scene, settings);
  print_summary(scene.name, atlas, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return atlas;
}

// Interiors of two counter-clockwise triangles intersect, with `tol` (uv units) of slack for
// rounding: a separating edge may have the other triangle up to tol inside it.
bool overlap(const Tri2& a, const Tri2& b, double tol) {
  auto separated = [tol](const Tri2& x, const Tri2& y) {
    for (int k = 0; k < 3; ++k) {
      const glm::dvec2 p = x[k], q = x[(k + 1) % 3];
      const double len = glm::length(q - p);
      bool all = true;
      for (int v = 0; v < 3; ++v) all = all && orient(p, q, y[v]) <= tol * len;
      if (all) return true;
    }
    return false;
  };
  return !separated(a, b) && !separated(b, a);
}

double segment_distance(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
  const glm::dvec2 ab = b - a;
  const double len2 = glm::dot(ab, ab);
  const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - a - s * ab);
}

// Distance from p to the closed triangle (0 inside); degenerate triangles: to their edges.
double distance(const glm::dvec2& p, const Tri2& t) {
  const double a = area2(t);
  if (a > 0.0 && orient(t[0], t[1], p) >= 0.0 && orient(t[1], t[2], p) >= 0.0 && orient(t[2], t[0], p) >= 0.0) return 0.0;
  return std::min({segment_distance(p, t[0], t[1]), segment_distance(p, t[1], t[2]), segment_distance(p, t[2], t[0])});
}

Tri2 at_level(const Tri2& t, uint32_t level) {
  const double s = 1.0 / double(1u << level);
  return {t[0] * s, t[1] * s, t[2] * s};
}

glm::dvec3 random_bary(std::mt19937_64& gen) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double a = u(gen), b = u(gen);
  if (a + b > 1.0) {
    a = 1.0 - a;
    b = 1.0 - b;
  }
  return {1.0 - a - b, a, b};
}

// ---- (1) + (2): charts are injective, and similarities up to the projection's cosine ----------

void check_charts(const SurfaceScene& scene, const AtlasSettings& settings, const TexelAtlas& atlas) {
  const Flat flat = flatten(scene);
  const size_t n = flat.p.size();
  ASSERT_EQ(atlas.chart_of_triangle.size(), n);
  ASSERT_EQ(atlas.corner_uv.size(), n);
  const double rho = atlas.texels_per_unit;
  ASSERT_GT(rho, 0.0);
  const double cos_max = std::cos(settings.max_normal_angle_deg * 3.14159265358979323846 / 180.0);
  std::vector<int> seen(n, 0);
  uint32_t first_of_mesh = 0;
  std::vector<uint32_t> mesh_of(n);
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    for (size_t t = 0; t < scene.meshes[m].triangles.size(); ++t) mesh_of[first_of_mesh + t] = m;
    first_of_mesh += static_cast<uint32_t>(scene.meshes[m].triangles.size());
  }
  for (uint32_t c = 0; c < atlas.charts.size(); ++c) {
    const Chart& chart = atlas.charts[c];
    ASSERT_FALSE(chart.triangles.empty());
    ASSERT_LE(chart.triangles.size(), settings.max_chart_triangles);
    ASSERT_TRUE(std::is_sorted(chart.triangles.begin(), chart.triangles.end()));
    const uint32_t seed = chart.triangles[0];
    const glm::dvec3 ns = normal_of(flat.p[seed]);
    const bool seed_ok = !degenerate3(flat.p[seed]);
    for (uint32_t t : chart.triangles) {
      ASSERT_LT(t, n);
      ++seen[t];
      EXPECT_EQ(atlas.chart_of_triangle[t], c);
      EXPECT_EQ(mesh_of[t], chart.mesh);
      const auto& uv = atlas.corner_uv[t];
      for (const auto& q : uv) ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y));
      const glm::dvec3 nt = normal_of(flat.p[t]);
      const double area3 = 0.5 * glm::length(nt);
      if (degenerate3(flat.p[t]) || !seed_ok) continue;
      // Orthogonal projection then a rotation and a scale by rho: no edge longer than rho times
      // its 3D length, the seed's exactly rho times, areas scaled by rho^2 cos(normal angle).
      const double cosine = glm::dot(nt, ns) / (glm::length(nt) * glm::length(ns));
      EXPECT_GE(cosine, cos_max - 1e-12) << scene.name << " triangle " << t;
      for (int k = 0; k < 3; ++k) {
        const double len3 = glm::length(flat.p[t][(k + 1) % 3] - flat.p[t][k]);
        const double len2 = glm::length(uv[(k + 1) % 3] - uv[k]);
        EXPECT_LE(len2, rho * len3 * (1.0 + 1e-9) + 1e-12) << scene.name << " triangle " << t;
        if (t == seed) {
          EXPECT_NEAR(len2, rho * len3, 1e-9 * rho * len3) << scene.name << " seed " << t;
        }
      }
      const double a2 = 0.5 * area2(uv);
      EXPECT_GT(a2, 0.0) << scene.name << " triangle " << t << " flips";
      EXPECT_NEAR(a2 / (rho * rho * area3), cosine, 1e-9) << scene.name << " triangle " << t;
    }
    // Injective: no two triangles' uv interiors intersect.
    std::vector<std::pair<glm::dvec2, glm::dvec2>> boxes;
    for (uint32_t t : chart.triangles) {
      const auto& uv = atlas.corner_uv[t];
      boxes.push_back({glm::min(uv[0], glm::min(uv[1], uv[2])), glm::max(uv[0], glm::max(uv[1], uv[2]))});
    }
    for (size_t a = 0; a < chart.triangles.size(); ++a) {
      for (size_t b = a + 1; b < chart.triangles.size(); ++b) {
        if (!(boxes[a].first.x < boxes[b].second.x && boxes[b].first.x < boxes[a].second.x && boxes[a].first.y < boxes[b].second.y &&
              boxes[b].first.y < boxes[a].second.y))
          continue;
        const Tri2& ta = atlas.corner_uv[chart.triangles[a]];
        const Tri2& tb = atlas.corner_uv[chart.triangles[b]];
        if (!(area2(ta) > 0.0 && area2(tb) > 0.0)) continue;
        const double scale = std::max(glm::length(boxes[a].second - boxes[a].first), glm::length(boxes[b].second - boxes[b].first));
        EXPECT_FALSE(overlap(ta, tb, 1e-9 * scale)) << scene.name << ": triangles " << chart.triangles[a] << " and " << chart.triangles[b]
                                                    << " overlap in chart " << c;
      }
    }
  }
  for (size_t t = 0; t < n; ++t) EXPECT_EQ(seen[t], 1) << "triangle " << t << " in " << seen[t] << " charts";
}

// ---- (3): packing --------------------------------------------------------------------------------

void check_packing(const TexelAtlas& atlas) {
  const uint32_t a = 1u << (atlas.levels - 1), pad = padding_texels(atlas.levels);
  ASSERT_EQ(pad, 2u * a);
  ASSERT_GT(atlas.width, 0u);
  EXPECT_EQ(atlas.width % (kTileTexels * a), 0u);
  EXPECT_EQ(atlas.height % (kTileTexels * a), 0u);
  const uint32_t gw = atlas.width / a, gh = atlas.height / a;
  std::vector<uint32_t> owner(uint64_t(gw) * gh, kNoTriangle);
  for (uint32_t c = 0; c < atlas.charts.size(); ++c) {
    const Chart& chart = atlas.charts[c];
    ASSERT_EQ(chart.origin.x % a, 0u);
    ASSERT_EQ(chart.origin.y % a, 0u);
    ASSERT_EQ(chart.size.x % a, 0u);
    ASSERT_EQ(chart.size.y % a, 0u);
    ASSERT_GE(chart.size.x, 2 * pad + a);
    ASSERT_GE(chart.size.y, 2 * pad + a);
    ASSERT_LE(chart.origin.x + chart.size.x, atlas.width);
    ASSERT_LE(chart.origin.y + chart.size.y, atlas.height);
    for (uint32_t y = chart.origin.y / a; y < (chart.origin.y + chart.size.y) / a; ++y)
      for (uint32_t x = chart.origin.x / a; x < (chart.origin.x + chart.size.x) / a; ++x) {
        uint32_t& o = owner[uint64_t(y) * gw + x];
        ASSERT_EQ(o, kNoTriangle) << "charts " << o << " and " << c << " overlap";
        o = c;
      }
    // Content: the chart's uvs lie pad texels inside its padded rectangle, and the content is
    // the rounded-up extent (no more than one grid step beyond it).
    glm::dvec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    for (uint32_t t : chart.triangles)
      for (const auto& q : atlas.corner_uv[t]) {
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
      }
    const double eps = 1e-9 * (atlas.width + atlas.height);
    EXPECT_NEAR(lo.x, chart.origin.x + pad, eps);
    EXPECT_NEAR(lo.y, chart.origin.y + pad, eps);
    EXPECT_LE(hi.x, chart.origin.x + chart.size.x - pad + eps);
    EXPECT_LE(hi.y, chart.origin.y + chart.size.y - pad + eps);
    EXPECT_GT(hi.x + a + eps, chart.origin.x + chart.size.x - pad);
    EXPECT_GT(hi.y + a + eps, chart.origin.y + chart.size.y - pad);
  }
}

// ---- (4) + (5): the triangle index against a brute-force evaluation of its rule -----------------

void check_triangle_index(const std::string& name, const TexelAtlas& atlas) {
  ASSERT_EQ(atlas.triangle_index.size(), atlas.levels);
  const double sqrt2 = std::sqrt(2.0);
  const uint32_t a = 1u << (atlas.levels - 1);
  const uint32_t gw = atlas.width / a;
  std::vector<uint32_t> chart_at(uint64_t(gw) * (atlas.height / a), kNoTriangle);
  for (uint32_t c = 0; c < atlas.charts.size(); ++c) {
    const Chart& chart = atlas.charts[c];
    for (uint32_t y = chart.origin.y / a; y < (chart.origin.y + chart.size.y) / a; ++y)
      for (uint32_t x = chart.origin.x / a; x < (chart.origin.x + chart.size.x) / a; ++x) chart_at[uint64_t(y) * gw + x] = c;
  }
  uint64_t mismatches = 0, held = 0, near_ties = 0;
  for (uint32_t level = 0; level < atlas.levels; ++level) {
    const uint32_t w = atlas.level_width(level), h = atlas.level_height(level);
    ASSERT_EQ(atlas.triangle_index[level].size(), uint64_t(w) * h);
    const uint32_t s = 1u << level;
    for (uint32_t j = 0; j < h; ++j) {
      for (uint32_t i = 0; i < w; ++i) {
        const uint32_t got = atlas.triangle_at(level, i, j);
        const uint32_t c = chart_at[uint64_t(j * s / a) * gw + i * s / a];
        const glm::dvec2 centre(i + 0.5, j + 0.5);
        uint32_t want = kNoTriangle;
        double best = std::numeric_limits<double>::infinity(), got_d = std::numeric_limits<double>::infinity();
        if (c != kNoTriangle) {
          for (uint32_t t : atlas.charts[c].triangles) {
            const double d = distance(centre, at_level(atlas.corner_uv[t], level));
            if (t == got) got_d = d;
            if (d <= sqrt2 && d < best) {
              best = d;
              want = t;
            }
          }
        }
        if (got != kNoTriangle) {
          ++held;
          ASSERT_NE(c, kNoTriangle) << name << ": a texel outside every chart holds a triangle";
          ASSERT_EQ(atlas.chart_of_triangle[got], c) << name << ": level " << level << " texel " << i << "," << j;
          EXPECT_LE(got_d, sqrt2 * (1.0 + 1e-12)) << name;
          // (5) its centre mapped through the triangle's affine map and back.
          const glm::dvec2 back = atlas_uv(atlas, got, texel_barycentric(atlas, got, level, i, j));
          if (area2(atlas.corner_uv[got]) > 0.0) {
            EXPECT_NEAR(back.x, centre.x * s, 1e-9 * (1.0 + centre.x * s)) << name;
            EXPECT_NEAR(back.y, centre.y * s, 1e-9 * (1.0 + centre.y * s)) << name;
          }
        }
        if (got != want) {
          // Only a near tie may choose differently (the atlas keeps float distances and counts
          // a centre within 1e-9 texels of a triangle as on it), and then a triangle as near.
          const bool near_tie = got != kNoTriangle && want != kNoTriangle && std::abs(got_d - best) <= 1e-6 * (1.0 + best);
          if (near_tie)
            ++near_ties;
          else
            ++mismatches;
          EXPECT_TRUE(near_tie) << name << ": level " << level << " texel " << i << "," << j << " holds " << got << " (distance " << got_d
                                << "), the rule gives " << want << " (" << best << ")";
          if (mismatches > 5) return;
        }
      }
    }
  }
  std::printf("[texel atlas] %-32s triangle index: %llu texels hold a triangle, all match the brute-force rule (%llu near ties)\n",
              name.c_str(), static_cast<unsigned long long>(held), static_cast<unsigned long long>(near_ties));
}

// Every point inside a triangle: at every level its four bilinear taps hold triangles of its
// chart within sqrt(2) texels, with the plain bilinear weights (nothing to renormalize).
void check_taps(const std::string& name, const TexelAtlas& atlas, uint32_t samples_per_triangle, uint32_t stride = 1) {
  std::mt19937_64 gen(12345);
  const double sqrt2 = std::sqrt(2.0);
  for (uint32_t t = 0; t < atlas.corner_uv.size(); t += stride) {
    if (!(area2(atlas.corner_uv[t]) > 0.0)) continue;
    const uint32_t c = atlas.chart_of_triangle[t];
    for (uint32_t k = 0; k < samples_per_triangle; ++k) {
      const glm::dvec2 uv = atlas_uv(atlas, t, random_bary(gen));
      for (uint32_t level = 0; level < atlas.levels; ++level) {
        const auto taps = bilinear_taps(atlas, uv, level);
        const glm::dvec2 f = uv / double(1u << level) - 0.5 - glm::floor(uv / double(1u << level) - 0.5);
        const double plain[4] = {(1 - f.x) * (1 - f.y), f.x * (1 - f.y), (1 - f.x) * f.y, f.x * f.y};
        double sum = 0.0;
        for (int q = 0; q < 4; ++q) {
          const Tap& tap = taps[q];
          sum += tap.weight;
          EXPECT_NEAR(tap.weight, plain[q], 1e-12) << name;
          const uint32_t held = atlas.triangle_at(level, tap.texel.x, tap.texel.y);
          ASSERT_NE(held, kNoTriangle) << name << ": triangle " << t << " level " << level;
          ASSERT_EQ(atlas.chart_of_triangle[held], c) << name;
          const glm::dvec2 centre(tap.texel.x + 0.5, tap.texel.y + 0.5);
          EXPECT_LE(distance(centre, at_level(atlas.corner_uv[held], level)), sqrt2 * (1.0 + 1e-12)) << name;
          EXPECT_LE(glm::length(centre - uv / double(1u << level)), sqrt2) << name;
        }
        EXPECT_NEAR(sum, 1.0, 1e-12) << name;
      }
    }
  }
}

// Texels whose centre lies inside a triangle hold it (or, on a shared edge, a lower id that
// also contains the centre).
void check_inside(const std::string& name, const TexelAtlas& atlas) {
  for (uint32_t level = 0; level < atlas.levels; ++level) {
    for (uint32_t t = 0; t < atlas.corner_uv.size(); ++t) {
      const Tri2 q = at_level(atlas.corner_uv[t], level);
      const double a2 = area2(q);
      if (!(a2 > 0.0)) continue;
      const glm::dvec2 lo = glm::min(q[0], glm::min(q[1], q[2])), hi = glm::max(q[0], glm::max(q[1], q[2]));
      for (int64_t j = int64_t(std::floor(lo.y)); j <= int64_t(hi.y); ++j)
        for (int64_t i = int64_t(std::floor(lo.x)); i <= int64_t(hi.x); ++i) {
          const glm::dvec2 p(double(i) + 0.5, double(j) + 0.5);
          // Signed distances (level-L texels) to the edges' lines, positive inside.
          double margin = std::numeric_limits<double>::infinity();
          for (int k = 0; k < 3; ++k) margin = std::min(margin, orient(q[k], q[(k + 1) % 3], p) / glm::length(q[(k + 1) % 3] - q[k]));
          if (margin < -1e-12) continue;
          const uint32_t got = atlas.triangle_at(level, uint32_t(i), uint32_t(j));
          if (margin > 1e-8) {
            EXPECT_EQ(got, t) << name << " level " << level << " texel " << i << "," << j;
          } else {  // on an edge (up to rounding): the lowest id among the triangles there
            ASSERT_NE(got, kNoTriangle);
            EXPECT_LE(got, t) << name;
            EXPECT_LE(distance(p, at_level(atlas.corner_uv[got], level)), 1e-8) << name;
          }
        }
    }
  }
}

TEST(TexelAtlas, ChartsAreInjectiveSimilaritiesPackedDisjointly) {
  for (const auto& [scene, settings] : small_scenes()) {
    const TexelAtlas atlas = timed_build(scene, settings);
    EXPECT_EQ(atlas.levels, settings.levels);
    check_charts(scene, settings, atlas);
    check_packing(atlas);
  }
}

TEST(TexelAtlas, TriangleIndexFollowsItsRule) {
  for (const auto& [scene, settings] : small_scenes()) {
    const TexelAtlas atlas = build_texel_atlas(scene, settings);
    check_triangle_index(scene.name, atlas);
    check_inside(scene.name, atlas);
  }
}

TEST(TexelAtlas, BilinearTapsOfSurfacePointsHitTheirChart) {
  for (const auto& [scene, settings] : small_scenes()) {
    const TexelAtlas atlas = build_texel_atlas(scene, settings);
    check_taps(scene.name, atlas, 8);
  }
}

// The helicoid's projection wraps over itself: some chart must have been cut by the overlap
// rule (two turns in one plane would fold), and what remains is injective (checked above).
TEST(TexelAtlas, OverlapRuleCutsAWrappingSurface) {
  AtlasSettings s;
  s.target_texels = double(1 << 15);
  s.max_chart_triangles = 100000;
  s.max_normal_angle_deg = 89.0;
  const SurfaceScene scene = scene_of("helicoid", {helicoid(2.5, 0.05, 48, 3)});
  const TexelAtlas atlas = build_texel_atlas(scene, s);
  const size_t n = atlas.corner_uv.size();
  // The strip's normals are within atan(pitch / (2 pi 0.3)) ~ 1.5 degrees of +z: only
  // overlaps can split it, and 2.5 turns need at least 3 charts of less than one turn each.
  EXPECT_GE(atlas.charts.size(), 3u);
  for (const auto& c : atlas.charts) EXPECT_LT(c.triangles.size(), n / 2);
  check_charts(scene, s, atlas);
}

// A cube's faces are flat squares at right angles: every face is one chart (60 degrees keeps
// neighbours apart), the minimum-area rectangle is the face itself, side * rho texels.
TEST(TexelAtlas, CubeFacesAreChartsOfTheirOwnSize) {
  AtlasSettings s;
  s.target_texels = double(1 << 16);
  const uint32_t n = 4;
  const double half = 0.7;
  const SurfaceScene scene = scene_of("cube", {scene_mesh(make_cube_surface(glm::dvec3(0.1, 0.2, 0.3), half, n), "cube")});
  const TexelAtlas atlas = build_texel_atlas(scene, s);
  ASSERT_EQ(atlas.charts.size(), 6u);
  const double rho = atlas.texels_per_unit;
  EXPECT_NEAR(rho, std::sqrt(s.target_texels / (6 * 4 * half * half)), 1e-9 * rho);
  for (const auto& chart : atlas.charts) {
    EXPECT_EQ(chart.triangles.size(), 2 * n * n);
    glm::dvec2 lo(1e300), hi(-1e300);
    for (uint32_t t : chart.triangles)
      for (const auto& q : atlas.corner_uv[t]) {
        lo = glm::min(lo, q);
        hi = glm::max(hi, q);
      }
    EXPECT_NEAR(hi.x - lo.x, 2 * half * rho, 1e-9 * rho);
    EXPECT_NEAR(hi.y - lo.y, 2 * half * rho, 1e-9 * rho);
  }
  // Every level-0 texel centre inside the faces' content is covered: 6 faces of (2 half rho)^2
  // texels, up to the boundary's rounding (a perimeter's worth of texels).
  const double content = 6 * std::pow(2 * half * rho, 2);
  const double covered = double(atlas.covered_texels_level0());
  EXPECT_NEAR(covered, content, 6 * 4 * (2 * half * rho + 1));
}

// A 3 x 1 rectangle turned 30 degrees about its normal in a tilted plane, split into a fan of
// triangles about an off-centre point: its minimum-area rectangle is itself, laid out landscape
// (3 rho x 1 rho), whatever the frame the seed's normal gives.
TEST(TexelAtlas, MinimumAreaRectangleLandscape) {
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const glm::dvec3 a0 = glm::normalize(glm::cross(n, glm::dvec3(0, 0, 1)));
  const glm::dvec3 b0 = glm::cross(n, a0);
  const double c = std::cos(0.5235987755982988), s_ = std::sin(0.5235987755982988);
  const glm::dvec3 a = c * a0 + s_ * b0, b = -s_ * a0 + c * b0;
  SceneMesh m;
  m.name = "rectangle";
  const glm::dvec3 o(0.2, 0.4, -0.1);
  m.positions = {o, o + 3.0 * a, o + 3.0 * a + b, o + b, o + 1.1 * a + 0.3 * b};
  m.triangles = {{4, 0, 1}, {4, 1, 2}, {4, 2, 3}, {4, 3, 0}};
  AtlasSettings settings;
  settings.texels_per_unit = 41.0;
  const TexelAtlas atlas = build_texel_atlas(scene_of("rectangle", {m}), settings);
  ASSERT_EQ(atlas.charts.size(), 1u);
  glm::dvec2 lo(1e300), hi(-1e300);
  for (const auto& uv : atlas.corner_uv)
    for (const auto& q : uv) {
      lo = glm::min(lo, q);
      hi = glm::max(hi, q);
    }
  EXPECT_NEAR(hi.x - lo.x, 3.0 * 41.0, 1e-9);
  EXPECT_NEAR(hi.y - lo.y, 1.0 * 41.0, 1e-9);
  // Content 123 x 41 rounded up to multiples of 8 (4 levels), 16 texels of padding each side.
  EXPECT_EQ(atlas.charts[0].size, glm::uvec2(128 + 32, 48 + 32));
}

// texels_per_unit given: used as is; 0: the charts' 3D area times rho^2 is the target.
TEST(TexelAtlas, DensityFromTargetOrGiven) {
  const SurfaceScene scene = make_furnace(0.5, 1.0, 2);
  double area = 0.0;
  for (const auto& p : flatten(scene).p) area += 0.5 * glm::length(normal_of(p));
  AtlasSettings s;
  s.target_texels = 20000.0;
  EXPECT_NEAR(build_texel_atlas(scene, s).texels_per_unit, std::sqrt(20000.0 / area), 1e-12 * std::sqrt(20000.0 / area));
  s.texels_per_unit = 37.5;
  const TexelAtlas given = build_texel_atlas(scene, s);
  EXPECT_EQ(given.texels_per_unit, 37.5);
  // Same input, same atlas.
  const TexelAtlas again = build_texel_atlas(scene, s);
  EXPECT_EQ(given.width, again.width);
  EXPECT_EQ(given.height, again.height);
  EXPECT_EQ(given.triangle_index, again.triangle_index);
  EXPECT_EQ(given.chart_of_triangle, again.chart_of_triangle);
}

// ---- (6) level selection and taps, by hand -------------------------------------------------------

TEST(TexelAtlas, SelectLevel) {
  EXPECT_EQ(select_level(1.0, 0.0, 4), 0u);
  EXPECT_EQ(select_level(0.3, 0.0, 4), 0u);
  EXPECT_EQ(select_level(1.99, 0.0, 4), 0u);
  EXPECT_EQ(select_level(2.0, 0.0, 4), 1u);
  EXPECT_EQ(select_level(3.9, 0.0, 4), 1u);
  EXPECT_EQ(select_level(4.0, 0.0, 4), 2u);
  EXPECT_EQ(select_level(8.0, 0.0, 4), 3u);
  EXPECT_EQ(select_level(1e30, 0.0, 4), 3u);
  EXPECT_EQ(select_level(1e30, 0.0, 1), 0u);
  EXPECT_EQ(select_level(std::numeric_limits<double>::quiet_NaN(), 0.0, 4), 0u);
  EXPECT_EQ(select_level(std::numeric_limits<double>::infinity(), 0.0, 4), 0u);
  EXPECT_EQ(select_level(0.0, 0.0, 4), 0u);
  EXPECT_EQ(select_level(-2.0, 3.0, 4), 0u);
  // Bias: log2(1) + 1 = 1; log2(2) - 1 = 0; log2(3.9) + 0.5 = 2.46; log2(6) - 0.7 = 1.88.
  EXPECT_EQ(select_level(1.0, 1.0, 4), 1u);
  EXPECT_EQ(select_level(2.0, -1.0, 4), 0u);
  EXPECT_EQ(select_level(3.9, 0.5, 4), 2u);
  EXPECT_EQ(select_level(6.0, -0.7, 4), 1u);
  EXPECT_EQ(select_level(1.0, -5.0, 4), 0u);
  EXPECT_EQ(select_level(1.0, 100.0, 4), 3u);
  EXPECT_EQ(select_level(1.0, std::numeric_limits<double>::quiet_NaN(), 4), 0u);
}

TexelAtlas hand_atlas() {
  TexelAtlas a;
  a.width = 16;
  a.height = 16;
  a.levels = 2;
  a.triangle_index = {std::vector<uint32_t>(256, 0u), std::vector<uint32_t>(64, 0u)};
  return a;
}

TEST(TexelAtlas, BilinearTapsByHand) {
  TexelAtlas a = hand_atlas();
  auto expect = [](const std::array<Tap, 4>& taps, const std::array<glm::uvec2, 4>& texels, const std::array<double, 4>& w) {
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(taps[k].texel, texels[k]) << "tap " << k;
      EXPECT_NEAR(taps[k].weight, w[k], 1e-15) << "tap " << k;
    }
  };
  // At a level-0 texel centre: that texel alone.
  expect(bilinear_taps(a, {5.5, 7.5}, 0), {glm::uvec2(5, 7), {6, 7}, {5, 8}, {6, 8}}, {1, 0, 0, 0});
  // A quarter of the way to the right neighbour.
  expect(bilinear_taps(a, {5.75, 7.5}, 0), {glm::uvec2(5, 7), {6, 7}, {5, 8}, {6, 8}}, {0.75, 0.25, 0, 0});
  // Level 1: uv (4, 4) -> t = (1.5, 1.5): four equal taps around (1, 1).
  expect(bilinear_taps(a, {4.0, 4.0}, 1), {glm::uvec2(1, 1), {2, 1}, {1, 2}, {2, 2}}, {0.25, 0.25, 0.25, 0.25});
  // uv (5, 2.5) at level 1: t = (2, 0.75).
  expect(bilinear_taps(a, {5.0, 2.5}, 1), {glm::uvec2(2, 0), {3, 0}, {2, 1}, {3, 1}}, {0.25, 0.0, 0.75, 0.0});
  // Clamped at the corner: t = (-0.5, -0.5) -> texels -1 and 0 both clamp to 0.
  expect(bilinear_taps(a, {0.0, 0.0}, 0), {glm::uvec2(0, 0), {0, 0}, {0, 0}, {0, 0}}, {0.25, 0.25, 0.25, 0.25});
  expect(bilinear_taps(a, {16.0, 3.0}, 0), {glm::uvec2(15, 2), {15, 2}, {15, 3}, {15, 3}}, {0.25, 0.25, 0.25, 0.25});
  // A texel without triangle: weight 0, the rest renormalized (0.75 0.25 -> 1 0 at (6,7) empty;
  // four quarters with one empty -> thirds).
  a.triangle_index[0][7 * 16 + 6] = kNoTriangle;
  expect(bilinear_taps(a, {5.75, 7.5}, 0), {glm::uvec2(5, 7), {6, 7}, {5, 8}, {6, 8}}, {1, 0, 0, 0});
  expect(bilinear_taps(a, {6.0, 8.0}, 0), {glm::uvec2(5, 7), {6, 7}, {5, 8}, {6, 8}}, {1.0 / 3, 0, 1.0 / 3, 1.0 / 3});
  // All four empty: all zero.
  for (uint32_t t : {5u, 6u}) a.triangle_index[0][8 * 16 + t] = kNoTriangle;
  a.triangle_index[0][7 * 16 + 5] = kNoTriangle;
  expect(bilinear_taps(a, {6.0, 8.0}, 0), {glm::uvec2(5, 7), {6, 7}, {5, 8}, {6, 8}}, {0, 0, 0, 0});
}

TEST(TexelAtlas, OffsetsAndCounts) {
  TexelAtlas a;
  a.width = 64;
  a.height = 32;
  a.levels = 3;
  EXPECT_EQ(a.texel_offset(0), 0u);
  EXPECT_EQ(a.texel_offset(1), 64u * 32);
  EXPECT_EQ(a.texel_offset(2), 64u * 32 + 32 * 16);
  EXPECT_EQ(a.texel_count(), 64u * 32 + 32 * 16 + 16 * 8);
  EXPECT_EQ(a.tile_offset(1), 8u * 4);
  EXPECT_EQ(a.tile_offset(2), 8u * 4 + 4 * 2);
  EXPECT_EQ(a.tile_count(), 8u * 4 + 4 * 2 + 2 * 1);
}

TEST(TexelAtlas, TexelBarycentricRoundTrip) {
  const SurfaceScene scene = make_cornell_box();
  AtlasSettings s;
  s.target_texels = double(1 << 14);
  const TexelAtlas atlas = build_texel_atlas(scene, s);
  // A texel's centre mapped to its triangle's barycentrics and back, at all levels, for every
  // texel near every triangle (also outside it: extrapolated).
  for (uint32_t t = 0; t < atlas.corner_uv.size(); ++t)
    for (uint32_t level = 0; level < atlas.levels; ++level)
      for (uint32_t j = 0; j < atlas.level_height(level); j += 3)
        for (uint32_t i = 0; i < atlas.level_width(level); i += 3) {
          const double s_ = double(1u << level);
          const glm::dvec3 b = texel_barycentric(atlas, t, level, i, j);
          EXPECT_NEAR(b.x + b.y + b.z, 1.0, 1e-9);
          const glm::dvec2 back = atlas_uv(atlas, t, b);
          ASSERT_NEAR(back.x, (i + 0.5) * s_, 1e-9 * (1.0 + (i + 0.5) * s_));
          ASSERT_NEAR(back.y, (j + 0.5) * s_, 1e-9 * (1.0 + (j + 0.5) * s_));
        }
}

// ---- (7) degenerate input ------------------------------------------------------------------------

TEST(TexelAtlas, DegenerateTrianglesAreHarmless) {
  SceneMesh m = scene_mesh(make_cube_surface(glm::dvec3(0.0), 1.0, 2), "cube with slivers");
  const uint32_t base = static_cast<uint32_t>(m.positions.size());
  m.positions.push_back({3.0, 0.0, 0.0});
  m.positions.push_back({4.0, 0.0, 0.0});
  m.positions.push_back({5.0, 0.0, 0.0});          // collinear with the two before
  m.positions.push_back({4.0, 1e-30, 0.0});        // an area of ~1e-30
  const uint32_t first_degenerate = static_cast<uint32_t>(m.triangles.size());
  m.triangles.push_back({base, base + 1, base + 2});      // collinear
  m.triangles.push_back({base, base, base + 1});          // repeated vertex
  m.triangles.push_back({base + 1, base + 1, base + 1});  // a point
  m.triangles.push_back({base, base + 2, base + 3});      // near-zero area
  m.triangles.push_back(m.triangles[0]);                  // a duplicate of a cube triangle
  const SurfaceScene scene = scene_of("slivers", {m});
  AtlasSettings s;
  s.target_texels = double(1 << 14);
  const TexelAtlas atlas = build_texel_atlas(scene, s);
  for (uint32_t t = first_degenerate; t < first_degenerate + 4; ++t) {
    const Chart& chart = atlas.charts[atlas.chart_of_triangle[t]];
    EXPECT_EQ(chart.triangles.size(), 1u) << "degenerate triangle " << t << " shares a chart";
    const glm::dvec3 b = texel_barycentric(atlas, t, 0, chart.origin.x + 1, chart.origin.y + 1);
    EXPECT_EQ(b, glm::dvec3(1.0 / 3.0)) << t;
  }
  // The duplicate overlaps its twin exactly: never in the same chart.
  EXPECT_NE(atlas.chart_of_triangle[0], atlas.chart_of_triangle[first_degenerate + 4]);
  for (const auto& uv : atlas.corner_uv)
    for (const auto& q : uv) ASSERT_TRUE(std::isfinite(q.x) && std::isfinite(q.y));
  for (uint32_t t = 0; t < atlas.corner_uv.size(); ++t)
    for (uint32_t level = 0; level < atlas.levels; ++level) {
      const glm::dvec3 b = texel_barycentric(atlas, t, level, 3, 5);
      ASSERT_TRUE(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z));
    }
  check_charts(scene, s, atlas);
  check_packing(atlas);
  check_triangle_index(scene.name, atlas);
  check_taps(scene.name, atlas, 4);
}

TEST(TexelAtlas, EmptySceneGivesTheSmallestAtlas) {
  AtlasSettings s;
  s.levels = 3;
  const TexelAtlas atlas = build_texel_atlas(scene_of("empty", {}), s);
  EXPECT_EQ(atlas.width, kTileTexels * 4);
  EXPECT_EQ(atlas.height, kTileTexels * 4);
  EXPECT_TRUE(atlas.charts.empty());
  EXPECT_EQ(atlas.used_texels(), 0u);
  EXPECT_EQ(atlas.triangle_index.size(), 3u);
  EXPECT_EQ(atlas.tile_count(), 16u + 4u + 1u);  // 32 x 32, 16 x 16, 8 x 8 texels
}

// ---- (8) bad settings ----------------------------------------------------------------------------

TEST(TexelAtlas, BadSettingsNameTheScene) {
  const SurfaceScene scene = make_furnace(0.5, 1.0, 1);
  auto fails = [&](const AtlasSettings& s, const std::string& words) {
    test::expect_input_error([&] { (void)build_texel_atlas(scene, s); }, scene.name, words);
  };
  AtlasSettings s;
  s.levels = 0;
  fails(s, "levels");
  s.levels = kMaxLevels + 1;
  fails(s, "levels");
  s = {};
  for (double angle : {0.0, 90.0, -10.0, 120.0, std::numeric_limits<double>::quiet_NaN()}) {
    s.max_normal_angle_deg = angle;
    fails(s, "angle");
  }
  s = {};
  s.max_chart_triangles = 0;
  fails(s, "at least one triangle");
  s = {};
  for (double target : {0.0, -5.0, std::numeric_limits<double>::infinity()}) {
    s.target_texels = target;
    fails(s, "target");
  }
  s = {};
  s.texels_per_unit = -1.0;
  fails(s, "texels per unit");
  s = {};
  s.max_side = 256;
  s.target_texels = double(1 << 20);
  fails(s, "lower texel density");
  s = {};
  s.texels_per_unit = 1e12;
  fails(s, "lower texel density");
}

// ---- A bigger scene: the invariants that stay cheap, and the build time (printed, not asserted)

TEST(TexelAtlas, LargeSphere) {
  const SurfaceScene scene = make_furnace(0.5, 1.0, 6);  // 81920 triangles
  AtlasSettings s;
  s.target_texels = double(1 << 22);
  const TexelAtlas atlas = timed_build(scene, s);
  EXPECT_EQ(atlas.corner_uv.size(), 81920u);
  check_packing(atlas);
  check_taps(scene.name, atlas, 1, 7);
  // Most of the atlas's level 0 is the surface: the target is what the triangles cover.
  const double covered = double(atlas.covered_texels_level0());
  EXPECT_GT(covered, 0.9 * s.target_texels);
  EXPECT_LT(covered, 1.01 * s.target_texels);
}

}  // namespace
}  // namespace prismoid::texel
