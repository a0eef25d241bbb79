#include "renderer/reference/htex_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "renderer/surface/htex/htex_layout.hpp"
#include "scene/generators.hpp"
#include "support/test_meshes.hpp"

namespace prismoid::reference {
namespace {

using htex::AtlasLayout;
using htex::LayoutOptions;
using htex::TexelAddress;

// A smooth function of position, values of order 1, no symmetry the meshes share.
double smooth(const glm::dvec3& p) { return std::sin(1.3 * p.x + 0.4) + 0.7 * std::cos(0.9 * p.y - 0.6 * p.z) + 0.3 * p.x * p.z; }

HtexShader smooth_shader() {
  return [](uint32_t, const htex::TexelPoint& t) { return glm::dvec4(smooth(t.position), 0.0, 0.0, 0.0); };
}

glm::dvec3 point_of(const HalfedgeMesh& m, uint32_t face, const glm::dvec3& b) {
  const auto& f = m.faces[face];
  return b[0] * m.positions[f[0]] + b[1] * m.positions[f[1]] + b[2] * m.positions[f[2]];
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

LayoutOptions fixed_side(uint32_t log2) {
  LayoutOptions o;
  o.min_log2 = o.max_log2 = log2;
  return o;
}

std::vector<HalfedgeMesh> sphere_and_cube(uint32_t sphere_subdivisions = 2, uint32_t cube_n = 2) {
  std::vector<HalfedgeMesh> meshes;
  meshes.push_back(build_halfedge_mesh(make_icosphere(glm::dvec3(0.0), 1.0, sphere_subdivisions), NonManifold::Reject));
  meshes.push_back(build_halfedge_mesh(make_cube_surface(glm::dvec3(0.2, -0.1, 0.3), 0.8, cube_n), NonManifold::Reject));
  return meshes;
}

// ---- Charts -----------------------------------------------------------------------------------

TEST(HtexCharts, LocateAndBarycentricAreInverse) {
  std::mt19937_64 gen(1);
  for (int i = 0; i < 1000; ++i) {
    const glm::dvec3 b = random_bary(gen);
    const htex::HalfedgePoint p = htex::locate_in_face(7, b);
    EXPECT_EQ(HalfedgeMesh::face(p.halfedge), 7);
    EXPECT_GE(p.uv.x, 0.0);
    EXPECT_GE(p.uv.y, 0.0);
    EXPECT_LE(p.uv.x + p.uv.y, 1.0 + 1e-15);
    const glm::dvec3 back = htex::face_barycentric(p.halfedge, p.uv);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], b[k], 1e-15);
  }
  // The centroid is (0, 0) of every halfedge triangle; a vertex is (1, 0) of its outgoing one.
  EXPECT_EQ(htex::locate_in_face(0, glm::dvec3(1.0 / 3.0)).uv, glm::dvec2(0.0));
  const htex::HalfedgePoint v = htex::locate_in_face(0, {0.0, 1.0, 0.0});
  EXPECT_EQ(v.uv, glm::dvec2(1.0, 0.0));
  EXPECT_EQ(v.halfedge, 1);
}

TEST(HtexCharts, QuadCornersAreTheFaceCentresAndTheEdgesEnds) {
  const auto meshes = sphere_and_cube(1, 1);
  for (const HalfedgeMesh& m : meshes)
    for (uint32_t e = 0; e < m.edge_count(); ++e) {
      const int32_t p = m.edge_halfedge[e], t = m.twin[p];
      auto at = [&](glm::dvec2 xy) {
        const htex::QuadSurfacePoint s = htex::quad_surface_point(m, e, xy);
        return point_of(m, s.face, s.bary);
      };
      const auto near = [](glm::dvec3 a, glm::dvec3 b) { return glm::length(a - b) < 1e-14; };
      EXPECT_TRUE(near(at({0, 0}), face_center(m, HalfedgeMesh::face(p))));
      EXPECT_TRUE(near(at({1, 0}), m.positions[m.vertex(p)]));
      EXPECT_TRUE(near(at({0, 1}), m.positions[m.target(p)]));
      EXPECT_TRUE(near(at({1, 1}), face_center(m, HalfedgeMesh::face(t))));
      // The diagonal is the edge, the same point from either half.
      EXPECT_TRUE(near(at({0.3, 0.7}), 0.3 * m.positions[m.vertex(p)] + 0.7 * m.positions[m.target(p)]));
    }
}

// A point of a quad, taken to the surface and back through the Htex lookup's charts, lands on
// the same quad coordinates: the twin's 1 - (u, v) undoes the primary's (u, v) across the edge.
TEST(HtexCharts, QuadToSurfaceToQuadRoundTrips) {
  const auto meshes = sphere_and_cube(1, 2);
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (const HalfedgeMesh& m : meshes)
    for (uint32_t e = 0; e < m.edge_count(); ++e)
      for (int s = 0; s < 20; ++s) {
        const glm::dvec2 xy(u(gen), u(gen));
        const htex::QuadSurfacePoint sp = htex::quad_surface_point(m, e, xy);
        ASSERT_FALSE(sp.ghost);
        bool found = false;
        for (const htex::QuadPoint& q : htex::face_point_quads(m, sp.face, sp.bary))
          if (q.edge == e) {
            EXPECT_NEAR(q.xy.x, xy.x, 1e-14);
            EXPECT_NEAR(q.xy.y, xy.y, 1e-14);
            found = true;
          }
        EXPECT_TRUE(found);
      }
}

// ---- Layout -----------------------------------------------------------------------------------

TEST(HtexLayout, SideIsChosenFromTheLargestQuad) {
  // Independent stretch: the longest image of a unit direction, sampled every 0.05 degree
  // (relative error below (pi / 3600)^2 / 8 ~ 1e-7).
  auto sampled_stretch = [](const HalfedgeMesh& m, uint32_t e) {
    double s = 0.0;
    for (int32_t h : {m.edge_halfedge[e], m.twin[m.edge_halfedge[e]]}) {
      if (h == kNoHalfedge) continue;
      const glm::dvec3 c = face_center(m, HalfedgeMesh::face(h));
      const glm::dvec3 a = m.positions[m.vertex(h)] - c, b = m.positions[m.target(h)] - c;
      for (int k = 0; k < 3600; ++k) {
        const double t = k * 3.141592653589793 / 3600;
        s = std::max(s, glm::length(std::cos(t) * a + std::sin(t) * b));
      }
    }
    return s;
  };
  std::vector<HalfedgeMesh> meshes = sphere_and_cube(2, 3);
  meshes.push_back(build_halfedge_mesh(test::make_disk(3, 0.4)));
  double largest[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i)
    for (uint32_t e = 0; e < meshes[i].edge_count(); ++e) {
      const double s = htex::quad_stretch(meshes[i], e);
      EXPECT_NEAR(s, sampled_stretch(meshes[i], e), 1e-6 * s);
      largest[i] = std::max(largest[i], s);
    }
  LayoutOptions options;
  options.texels_per_unit = 40.0;
  const AtlasLayout layout(meshes, options);
  for (int i = 0; i < 3; ++i) {
    const htex::MeshLayout& m = layout.meshes()[i];
    EXPECT_DOUBLE_EQ(m.largest_stretch, largest[i]);
    const double n = m.side(0);
    // The smallest power of two whose texels span at most 1/40 on the largest quad.
    EXPECT_LE(largest[i] / n, 1.0 / 40.0);
    EXPECT_GT(largest[i] / (n / 2), 1.0 / 40.0);
    EXPECT_EQ(m.levels, m.log2_side);
    EXPECT_EQ(m.side(m.levels - 1), 2u);
    std::printf("mesh %d: %zu quads, largest stretch %.4f, side %u, %u levels, %u x %u quads\n", i, meshes[i].edge_count(),
                largest[i], m.side(0), m.levels, m.columns, m.rows);
  }
  // Clamped to [min_log2, max_log2], and never below a side of 2.
  LayoutOptions tiny;
  tiny.texels_per_unit = 1e-3;
  tiny.min_log2 = 0;
  EXPECT_EQ(AtlasLayout(meshes, tiny).meshes()[0].side(0), 2u);
  LayoutOptions huge;
  huge.texels_per_unit = 1e6;
  huge.max_log2 = 5;
  EXPECT_EQ(AtlasLayout(meshes, huge).meshes()[1].side(0), 32u);
}

TEST(HtexLayout, EveryQuadTexelHasItsOwnVirtualTexelAndBack) {
  std::vector<HalfedgeMesh> meshes = sphere_and_cube(2, 3);
  meshes.push_back(build_halfedge_mesh(test::make_disk(3)));
  meshes.push_back(build_halfedge_mesh("empty", {}, {}));
  meshes.push_back(build_halfedge_mesh(make_cube_surface(glm::dvec3(5.0), 0.1, 1)));
  LayoutOptions options;
  options.texels_per_unit = 24.0;
  const AtlasLayout layout(meshes, options);
  ASSERT_EQ(layout.width() % htex::kGroupTexels, 0u);
  ASSERT_EQ(layout.height() % htex::kGroupTexels, 0u);
  std::vector<uint8_t> used(size_t(layout.width()) * layout.height(), 0);
  size_t texels = 0;
  for (uint32_t mi = 0; mi < meshes.size(); ++mi) {
    const htex::MeshLayout& m = layout.meshes()[mi];
    EXPECT_EQ(m.quad_count, meshes[mi].edge_count());
    for (uint32_t level = 0; level < m.levels; ++level) {
      EXPECT_EQ(m.origin[level].x % htex::kShadelTexels, 0u);
      EXPECT_EQ(m.origin[level].y % htex::kShadelTexels, 0u);
      const uint32_t n = m.side(level);
      for (uint32_t q = 0; q < m.quad_count; ++q) {
        EXPECT_EQ(layout.mesh_of_quad(m.first_quad + q), mi);
        for (uint32_t j = 0; j < n; ++j)
          for (uint32_t i = 0; i < n; ++i) {
            const TexelAddress t{m.first_quad + q, level, i, j};
            const glm::uvec2 v = layout.virtual_texel(t);
            ASSERT_LT(v.x, layout.width());
            ASSERT_LT(v.y, layout.height());
            uint8_t& slot = used[size_t(v.y) * layout.width() + v.x];
            ASSERT_EQ(slot, 0) << "two texels at (" << v.x << ", " << v.y << ")";
            slot = 1;
            ++texels;
            const auto back = layout.texel_at(v);
            ASSERT_TRUE(back.has_value());
            ASSERT_EQ(*back, t);
            const auto region = layout.region_of_shadel(layout.shadel_of(v));
            ASSERT_TRUE(region.has_value());
            EXPECT_EQ(region->mesh, mi);
            EXPECT_EQ(region->level, level);
          }
      }
    }
  }
  // Every other virtual texel is padding and says so.
  size_t padding = 0;
  for (uint32_t y = 0; y < layout.height(); ++y)
    for (uint32_t x = 0; x < layout.width(); ++x)
      if (!used[size_t(y) * layout.width() + x]) {
        ASSERT_FALSE(layout.texel_at({x, y}).has_value());
        ++padding;
      }
  std::printf("atlas %u x %u: %zu quad texels, %.1f%% padding\n", layout.width(), layout.height(), texels,
              100.0 * static_cast<double>(padding) / (double(layout.width()) * layout.height()));
  EXPECT_FALSE(layout.texel_at({layout.width(), 0}).has_value());
}

// ---- Lookup weights ---------------------------------------------------------------------------

void expect_partition_of_unity(const std::vector<HalfedgeMesh>& meshes, const AtlasLayout& layout, uint32_t mesh, uint32_t face,
                               const glm::dvec3& bary, double* min_alpha) {
  const htex::MeshLayout& m = layout.meshes()[mesh];
  for (uint32_t level = 0; level < m.levels; ++level) {
    const HtexFootprint fp = htex_footprint(meshes, layout, mesh, face, bary, level);
    ASSERT_GE(fp.count, 1u);
    ASSERT_LE(fp.count, 12u);
    double sum = 0.0;
    std::set<std::array<uint32_t, 4>> distinct;
    for (uint32_t k = 0; k < fp.count; ++k) {
      EXPECT_GT(fp.texels[k].weight, 0.0);
      sum += fp.texels[k].weight;
      const TexelAddress& t = fp.texels[k].texel;
      distinct.insert({t.quad, t.level, t.i, t.j});
      EXPECT_EQ(t.level, level);
    }
    EXPECT_EQ(distinct.size(), fp.count);
    EXPECT_NEAR(sum, 1.0, 4e-16);
    EXPECT_GE(fp.alpha, 0.25 - 1e-15);
    EXPECT_LE(fp.alpha, 3.0);
    *min_alpha = std::min(*min_alpha, fp.alpha);
  }
}

TEST(HtexLookup, WeightsAreNonNegativeAndSumToOneEverywhere) {
  std::vector<HalfedgeMesh> meshes = sphere_and_cube(1, 2);
  meshes.push_back(build_halfedge_mesh(test::make_disk(3, 0.3)));
  const AtlasLayout layout(meshes, fixed_side(4));
  std::mt19937_64 gen(5);
  double min_alpha = 1e300;
  for (uint32_t mi = 0; mi < meshes.size(); ++mi)
    for (uint32_t f = 0; f < meshes[mi].face_count(); ++f) {
      // Random points, the three vertices, the edges' midpoints and near-ends, the centre.
      std::vector<glm::dvec3> points = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0}, {0, 0.5, 0.5},
                                        {0.5, 0, 0.5}, glm::dvec3(1.0 / 3.0), {1 - 1e-9, 1e-9, 0}, {0.99, 0, 0.01}};
      for (int s = 0; s < 10; ++s) points.push_back(random_bary(gen));
      for (const glm::dvec3& b : points) expect_partition_of_unity(meshes, layout, mi, f, b, &min_alpha);
    }
  EXPECT_GE(min_alpha, 0.25 - 1e-15);
  // At a face's centre every quad reads its face-point corner texel with alpha 1/2 * 1/2.
  const HtexFootprint centre = htex_footprint(meshes, layout, 0, 3, glm::dvec3(1.0 / 3.0), 0);
  EXPECT_EQ(centre.count, 3u);
  EXPECT_NEAR(centre.alpha, 0.75, 1e-15);
}

// A boundary quad's lookups never reach texels wholly beyond its edge (i + j >= n + 1), and the
// row i + j = n that they do reach is made of ghost texels in the face's plane.
TEST(HtexLookup, BoundaryQuadsReadOnlyTheirHalfAndOneGhostRow) {
  std::vector<HalfedgeMesh> meshes = {build_halfedge_mesh(test::make_disk(3, 0.3))};
  const HalfedgeMesh& m = meshes[0];
  const AtlasLayout layout(meshes, fixed_side(3));
  std::mt19937_64 gen(6);
  size_t ghost_reads = 0;
  for (uint32_t f = 0; f < m.face_count(); ++f)
    for (int s = 0; s < 400; ++s) {
      glm::dvec3 b = random_bary(gen);
      if (s % 4 == 0) b[s % 3] = 0.0, b /= b[0] + b[1] + b[2];  // on an edge
      for (uint32_t level = 0; level < layout.meshes()[0].levels; ++level) {
        const HtexFootprint fp = htex_footprint(meshes, layout, 0, f, b, level);
        for (uint32_t k = 0; k < fp.count; ++k) {
          const TexelAddress& t = fp.texels[k].texel;
          const uint32_t n = layout.meshes()[0].side(level);
          if (!m.boundary(m.edge_halfedge[t.quad])) continue;
          EXPECT_LE(t.i + t.j, n) << "read beyond the boundary";
          const htex::TexelPoint tp = htex::texel_point(m, t.quad, n, t.i, t.j);
          EXPECT_EQ(tp.ghost, t.i + t.j == n);
          ghost_reads += tp.ghost;
        }
      }
    }
  EXPECT_GT(ghost_reads, 0u);
  // Ghost texels lie in their face's plane, less than a texel beyond the boundary edge.
  for (uint32_t e = 0; e < m.edge_count(); ++e) {
    const int32_t p = m.edge_halfedge[e];
    if (!m.boundary(p)) continue;
    const uint32_t n = 8;
    const auto& f = m.faces[HalfedgeMesh::face(p)];
    const glm::dvec3 normal = glm::normalize(glm::cross(m.positions[f[1]] - m.positions[f[0]], m.positions[f[2]] - m.positions[f[0]]));
    for (uint32_t i = 1; i < n; ++i) {
      const htex::TexelPoint g = htex::texel_point(m, e, n, i, n - i);
      ASSERT_TRUE(g.ghost);
      EXPECT_NEAR(glm::dot(g.position - m.positions[f[0]], normal), 0.0, 1e-14);
      EXPECT_LT(std::min({g.bary[0], g.bary[1], g.bary[2]}), 0.0);
    }
  }
}

// Filtering crosses an edge inside its quad: a point on an edge, read from either face, takes
// texels shaded on both sides of it (the twin's half of the quad).
TEST(HtexLookup, BilinearFootprintAtAnEdgeReadsTexelsOfBothFaces) {
  const auto meshes = sphere_and_cube(1, 2);
  const AtlasLayout layout(meshes, fixed_side(4));
  for (uint32_t mi = 0; mi < 2; ++mi) {
    const HalfedgeMesh& m = meshes[mi];
    const uint32_t n = layout.meshes()[mi].side(0);
    for (uint32_t e = 0; e < m.edge_count(); ++e) {
      const int32_t h = m.edge_halfedge[e], t = m.twin[h];
      for (int32_t from : {h, t}) {
        glm::dvec3 b(0.0);
        b[HalfedgeMesh::corner(from)] = 0.37, b[(HalfedgeMesh::corner(from) + 1) % 3] = 0.63;
        const HtexFootprint fp = htex_footprint(meshes, layout, mi, HalfedgeMesh::face(from), b, 0);
        std::set<uint32_t> faces;
        for (uint32_t k = 0; k < fp.count; ++k) {
          ASSERT_EQ(fp.texels[k].texel.quad, layout.meshes()[mi].first_quad + e);  // far from the ends: this quad only
          const TexelAddress& tx = fp.texels[k].texel;
          if (tx.i + tx.j != n - 1) faces.insert(htex::texel_point(m, e, n, tx.i, tx.j).face);
        }
        EXPECT_EQ(faces, (std::set<uint32_t>{uint32_t(HalfedgeMesh::face(h)), uint32_t(HalfedgeMesh::face(t))}));
      }
    }
  }
}

// Every quad around a vertex shades its corner texel at that vertex.
TEST(HtexLookup, VertexCornerTexelsAreShadedAtTheVertex) {
  const auto meshes = sphere_and_cube(1, 2);
  for (const HalfedgeMesh& m : meshes)
    for (uint32_t n : {2u, 8u})
      for (uint32_t e = 0; e < m.edge_count(); ++e) {
        const int32_t p = m.edge_halfedge[e];
        const htex::TexelPoint a = htex::texel_point(m, e, n, n - 1, 0), b = htex::texel_point(m, e, n, 0, n - 1);
        EXPECT_EQ(a.vertex, int32_t(m.vertex(p)));
        EXPECT_EQ(b.vertex, int32_t(m.target(p)));
        EXPECT_EQ(a.position, m.positions[m.vertex(p)]);
        EXPECT_EQ(b.position, m.positions[m.target(p)]);
        EXPECT_EQ(point_of(m, a.face, a.bary), m.positions[m.vertex(p)]);
        // Unsnapped, the same texels sit on the edge half a texel from its ends.
        const htex::TexelPoint raw = htex::texel_point(m, e, n, n - 1, 0, false);
        EXPECT_EQ(raw.vertex, -1);
        const glm::dvec3 expected = m.positions[m.vertex(p)] + (0.5 / n) * (m.positions[m.target(p)] - m.positions[m.vertex(p)]);
        EXPECT_LT(glm::length(raw.position - expected), 1e-14);
      }
}

// ---- Seamlessness -----------------------------------------------------------------------------

struct SeamGaps {
  double max_gap = 0.0;               // |value from one face - value from the other| on the edge
  double max_gap_past_half_texel = 0.0;  // the same, more than half a texel from the edge's ends
  double max_gap_off_edge = 0.0;      // 1e-9 into each face
  size_t samples = 0;
};

SeamGaps seam_gaps(const std::vector<HalfedgeMesh>& meshes, const AtlasLayout& layout, const HtexTexture& texture, uint32_t mi,
                   uint32_t level) {
  const HalfedgeMesh& m = meshes[mi];
  const double n = layout.meshes()[mi].side(level);
  std::vector<double> along = {0.0, 1e-12, 1e-6, 0.1 / n, 0.25 / n, 0.4999 / n, 0.5 / n, 0.5001 / n, 1.0 / n, 1.5 / n, 0.3, 0.5};
  for (size_t k = 0, count = along.size(); k < count; ++k) along.push_back(1.0 - along[k]);
  SeamGaps gaps;
  for (uint32_t e = 0; e < m.edge_count(); ++e) {
    const int32_t h = m.edge_halfedge[e], t = m.twin[h];
    if (t == kNoHalfedge) continue;
    const uint32_t fh = HalfedgeMesh::face(h), ft = HalfedgeMesh::face(t);
    const int kh = HalfedgeMesh::corner(h), kt = HalfedgeMesh::corner(t);
    for (double s : along) {
      // s: fraction of the way from start(h) to end(h); t runs the other way.
      glm::dvec3 bh(0.0), bt(0.0);
      bh[kh] = 1.0 - s, bh[(kh + 1) % 3] = s;
      bt[kt] = s, bt[(kt + 1) % 3] = 1.0 - s;
      const double vh = htex_lookup(meshes, layout, texture, mi, fh, bh, level).x;
      const double vt = htex_lookup(meshes, layout, texture, mi, ft, bt, level).x;
      const double gap = std::abs(vh - vt);
      gaps.max_gap = std::max(gaps.max_gap, gap);
      if (std::min(s, 1.0 - s) > 0.5 / n) gaps.max_gap_past_half_texel = std::max(gaps.max_gap_past_half_texel, gap);
      const double eps = 1e-9;
      glm::dvec3 oh = bh * (1.0 - eps), ot = bt * (1.0 - eps);
      oh[(kh + 2) % 3] = eps, ot[(kt + 2) % 3] = eps;
      const double off = std::abs(htex_lookup(meshes, layout, texture, mi, fh, oh, level).x -
                                  htex_lookup(meshes, layout, texture, mi, ft, ot, level).x);
      gaps.max_gap_off_edge = std::max(gaps.max_gap_off_edge, off);
      ++gaps.samples;
    }
  }
  return gaps;
}

TEST(HtexSeams, SphereAndCubeAreContinuousAcrossEveryEdgeAtEveryLevel) {
  const auto meshes = sphere_and_cube(2, 3);
  const AtlasLayout layout(meshes, fixed_side(5));
  HtexTexture texture(layout, 1);
  htex_shade_all(meshes, layout, smooth_shader(), texture);
  for (uint32_t mi = 0; mi < meshes.size(); ++mi)
    for (uint32_t level = 0; level < layout.meshes()[mi].levels; ++level) {
      const SeamGaps g = seam_gaps(meshes, layout, texture, mi, level);
      std::printf("mesh %u level %u (side %u): %zu edge points, largest gap %.3g on the edge, %.3g 1e-9 off it\n", mi, level,
                  layout.meshes()[mi].side(level), g.samples, g.max_gap, g.max_gap_off_edge);
      EXPECT_GT(g.samples, 1000u);
      EXPECT_LE(g.max_gap, 4e-15) << "mesh " << mi << " level " << level;
      EXPECT_LE(g.max_gap_off_edge, 1e-7) << "mesh " << mi << " level " << level;
    }
}

// The control: corner texels shaded half a texel along their edge instead of at the vertex.
// Then the faces on either side of an edge disagree within half a texel of its ends (where each
// also reads its other quads' corner texels), and only there.
TEST(HtexSeams, UnsnappedVertexCornersOpenSeamsNearVerticesOnly) {
  const auto meshes = sphere_and_cube(2, 3);
  const AtlasLayout layout(meshes, fixed_side(4));
  HtexTexture texture(layout, 1);
  htex_shade_all(meshes, layout, smooth_shader(), texture, false);
  for (uint32_t mi = 0; mi < meshes.size(); ++mi) {
    const SeamGaps g = seam_gaps(meshes, layout, texture, mi, 0);
    std::printf("mesh %u unsnapped: largest gap %.3g, %.3g past half a texel from the ends\n", mi, g.max_gap,
                g.max_gap_past_half_texel);
    EXPECT_GT(g.max_gap, 1e-3);
    EXPECT_LE(g.max_gap_past_half_texel, 4e-15);
  }
}

// Inside a face the blend does not depend on which halfedge triangle a point on a border
// between two of them is located in (the quarter-turn charts agree there).
TEST(HtexSeams, ContinuousAcrossHalfedgeTrianglesInsideAFace) {
  const auto meshes = sphere_and_cube(1, 2);
  const AtlasLayout layout(meshes, fixed_side(3));
  HtexTexture texture(layout, 1);
  htex_shade_all(meshes, layout, smooth_shader(), texture);
  std::mt19937_64 gen(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0.0;
  for (uint32_t mi = 0; mi < 2; ++mi)
    for (uint32_t f = 0; f < meshes[mi].face_count(); ++f)
      for (int s = 0; s < 30; ++s) {
        // On the segment from the centre to vertex k: the other two weights are equal.
        const int k = s % 3;
        const double w = u(gen) * 2.0 / 3.0 + 1.0 / 3.0;  // weight of vertex k in [1/3, 1]
        glm::dvec3 b((1.0 - w) / 2.0);
        b[k] = w;
        glm::dvec3 left = b, right = b;
        const double d = 1e-13;
        left[(k + 1) % 3] += d, left[(k + 2) % 3] -= d;
        right[(k + 1) % 3] -= d, right[(k + 2) % 3] += d;
        ASSERT_NE(htex::locate_in_face(f, left).halfedge, htex::locate_in_face(f, right).halfedge);
        for (uint32_t level = 0; level < layout.meshes()[mi].levels; ++level) {
          const double a = htex_lookup(meshes, layout, texture, mi, f, left, level).x;
          const double c = htex_lookup(meshes, layout, texture, mi, f, right, level).x;
          worst = std::max(worst, std::abs(a - c));
        }
      }
  EXPECT_LE(worst, 1e-10);
}

// ---- Accuracy ---------------------------------------------------------------------------------

// A bound on |grad smooth| over the box |x|, |z| <= 1.1 that holds both meshes:
// |df/dx| <= 1.3 + 0.3 * 1.1, |df/dy| <= 0.7 * 0.9, |df/dz| <= 0.7 * 0.6 + 0.3 * 1.1.
constexpr double kSmoothLipschitz = 1.91;

// The blend is a convex combination of texel values, each shaded at a point at most
// 1.5 sqrt(2) stretch / n from the looked-up point: its bilinear tap lies within sqrt(2) / n of
// the point in the unfolded chart, a vertex corner texel moves a further half texel along its
// edge (sqrt(2) / (2 n) in the chart), and a path on the surface through the shared legs and
// edges is at most `stretch` times longer than in the chart. So the error of a smooth f is at
// most |grad f| 1.5 sqrt(2) stretch / n: first order. Near vertices it is that order (the
// corner texels hold f(vertex) over a texel-sized patch); elsewhere bilinear interpolation is
// second order except in the one-texel bands along the charts' kinks (legs and edges), so the
// mean error is second order.
TEST(HtexAccuracy, ReconstructionErrorFallsWithQuadSide) {
  for (uint32_t mi = 0; mi < 2; ++mi) {
    std::vector<double> max_err, mean_err, vertex_err;
    for (uint32_t log2 = 2; log2 <= 6; ++log2) {
      const auto meshes = sphere_and_cube(1, 1);
      const AtlasLayout layout(meshes, fixed_side(log2));
      HtexTexture texture(layout, 1);
      htex_shade_all(meshes, layout, smooth_shader(), texture);
      const HalfedgeMesh& m = meshes[mi];
      const double n = layout.meshes()[mi].side(0), stretch = layout.meshes()[mi].largest_stretch;
      const double radius_bound = 1.5 * std::sqrt(2.0) * stretch / n * (1.0 + 1e-12);
      std::mt19937_64 gen(11);
      double worst = 0.0, sum = 0.0, near_vertex = 0.0, widest = 0.0;
      size_t count = 0;
      for (uint32_t f = 0; f < m.face_count(); ++f) {
        std::vector<glm::dvec3> points;
        for (int s = 0; s < 300; ++s) points.push_back(random_bary(gen));
        const size_t random_points = points.size();
        for (int k = 0; k < 3; ++k)
          for (double d : {0.1, 0.3, 0.5, 1.0}) {
            glm::dvec3 b(0.5 * d / n);
            b[k] = 1.0 - d / n;
            points.push_back(b);
          }
        for (size_t s = 0; s < points.size(); ++s) {
          const glm::dvec3 p = point_of(m, f, points[s]);
          const HtexFootprint fp = htex_footprint(meshes, layout, mi, f, points[s], 0);
          double radius = 0.0;
          for (uint32_t k = 0; k < fp.count; ++k) {
            const TexelAddress& t = fp.texels[k].texel;
            const htex::TexelPoint tp = htex::texel_point(m, t.quad - layout.meshes()[mi].first_quad, uint32_t(n), t.i, t.j);
            radius = std::max(radius, glm::length(tp.position - p));
          }
          widest = std::max(widest, radius * n / stretch);
          ASSERT_LE(radius, radius_bound);
          const double err = std::abs(htex_lookup(meshes, layout, texture, mi, f, points[s], 0).x - smooth(p));
          ASSERT_LE(err, kSmoothLipschitz * radius + 1e-15);
          if (s < random_points) {
            worst = std::max(worst, err);
            sum += err;
            ++count;
          } else {
            near_vertex = std::max(near_vertex, err);
          }
        }
      }
      max_err.push_back(worst);
      mean_err.push_back(sum / static_cast<double>(count));
      vertex_err.push_back(near_vertex);
      std::printf("mesh %u side %3u: mean error %.3e, max %.3e, near vertices %.3e; footprint radius %.3f stretch / n\n", mi,
                  uint32_t(n), mean_err.back(), worst, near_vertex, widest);
    }
    for (size_t i = 1; i < mean_err.size(); ++i) {
      const double mean_order = std::log2(mean_err[i - 1] / mean_err[i]);
      const double vertex_order = std::log2(vertex_err[i - 1] / vertex_err[i]);
      std::printf("mesh %u: orders per halving of the texel: mean %.2f, near vertices %.2f, max %.2f\n", mi, mean_order,
                  vertex_order, std::log2(max_err[i - 1] / max_err[i]));
      EXPECT_GE(mean_order, 1.8);
      EXPECT_LE(mean_order, 2.4);
      EXPECT_NEAR(vertex_order, 1.0, 0.05);
      EXPECT_LT(max_err[i], max_err[i - 1]);
    }
  }
}

// ---- Level of detail and marking ---------------------------------------------------------------

TEST(HtexLevelOfDetail, AllThreeQuadsSeeTheSameDerivativesAndLevel) {
  const auto meshes = sphere_and_cube(1, 1);
  const AtlasLayout layout(meshes, fixed_side(5));
  const htex::MeshLayout& ml = layout.meshes()[0];
  const double n = ml.side(0);
  std::mt19937_64 gen(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (uint32_t f = 0; f < meshes[0].face_count(); ++f) {
    const glm::dvec3 b = random_bary(gen);
    const htex::HalfedgePoint hp = htex::locate_in_face(f, b);
    const int k = HalfedgeMesh::corner(hp.halfedge), m = (k + 2) % 3;
    for (int lambda = 0; lambda < 4; ++lambda) {
      // Barycentric derivatives whose local (u, v) derivative along x has length 2^lambda / n.
      const double angle = u(gen) * 3.14159;
      const glm::dvec2 duv_x = std::ldexp(1.0, lambda) / n * glm::dvec2(std::cos(angle), std::sin(angle));
      const glm::dvec2 duv_y = 0.5 * glm::length(duv_x) * glm::dvec2(u(gen), u(gen)) / std::sqrt(2.0);
      auto bary_derivative = [&](glm::dvec2 d) {
        glm::dvec3 db(0.0);
        db[m] = -(d.x + d.y) / 3.0;
        db[k] = d.x + db[m];
        db[(k + 1) % 3] = d.y + db[m];
        return db;
      };
      const glm::dvec3 dbx = bary_derivative(duv_x), dby = bary_derivative(duv_y);
      EXPECT_NEAR(dbx[0] + dbx[1] + dbx[2], 0.0, 1e-15);
      EXPECT_NEAR(htex_level_of_detail(ml, f, b, dbx, dby), double(lambda), 1e-12);
      // Finite differences of each quad's coordinates: the same length for all three.
      const double eps = 1e-7;
      const auto at = htex::face_point_quads(meshes[0], f, b);
      const auto moved = htex::face_point_quads(meshes[0], f, b + eps * dbx);
      if (htex::locate_in_face(f, b + eps * dbx).halfedge != hp.halfedge) continue;  // crossed a leg
      for (int q = 0; q < 3; ++q) {
        ASSERT_EQ(at[q].edge, moved[q].edge);
        EXPECT_NEAR(glm::length(moved[q].xy - at[q].xy) / eps, glm::length(duv_x), 1e-6 * glm::length(duv_x));
      }
    }
  }
}

// The shadels the pre-Z pass marks for a lookup are exactly those holding its texels.
TEST(HtexLevelOfDetail, FootprintShadelsHoldEveryTexelTheLookupReads) {
  std::vector<HalfedgeMesh> meshes = sphere_and_cube(1, 2);
  meshes.push_back(build_halfedge_mesh(test::make_disk(2)));
  LayoutOptions options;
  options.texels_per_unit = 30.0;
  const AtlasLayout layout(meshes, options);
  std::mt19937_64 gen(17);
  size_t multi = 0;
  for (uint32_t mi = 0; mi < meshes.size(); ++mi)
    for (uint32_t f = 0; f < meshes[mi].face_count(); ++f)
      for (uint32_t level = 0; level < layout.meshes()[mi].levels; ++level) {
        const HtexFootprint fp = htex_footprint(meshes, layout, mi, f, random_bary(gen), level);
        const std::vector<uint32_t> shadels = htex_footprint_shadels(layout, fp);
        std::set<uint32_t> expected;
        for (uint32_t k = 0; k < fp.count; ++k) {
          const glm::uvec2 v = layout.virtual_texel(fp.texels[k].texel);
          expected.insert((v.y / 8) * (layout.width() / 8) + v.x / 8);
        }
        EXPECT_EQ(std::set<uint32_t>(shadels.begin(), shadels.end()), expected);
        EXPECT_EQ(shadels.size(), expected.size());
        for (uint32_t s : shadels) {
          const auto region = layout.region_of_shadel(s);
          ASSERT_TRUE(region.has_value());
          EXPECT_EQ(region->mesh, mi);
          EXPECT_EQ(region->level, level);
        }
        multi += shadels.size() > 1;
      }
  EXPECT_GT(multi, 0u);  // lookups near quad borders read from more than one shadel
}

}  // namespace
}  // namespace prismoid::reference
