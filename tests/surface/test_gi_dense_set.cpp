// The CPU half of ReSTIR GI in object space: the texel walk over the halfedge adjacency
// (renderer/surface/htex/htex_walk.hpp), the dense sample set and its neighbour table
// (gi_dense_set.hpp), and the path tracer's radiance leaving surface points (the reference the
// GPU passes are held to).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "renderer/reference/path_tracer.hpp"
#include "renderer/surface/gi/gi_dense_set.hpp"
#include "renderer/surface/htex/htex_layout.hpp"
#include "renderer/surface/htex/htex_walk.hpp"
#include "scene/halfedge_mesh.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "support/test_meshes.hpp"

namespace prismoid {
namespace {

using surface::GiDenseSet;
using surface::kNoNeighbour;

// Scenes with closed meshes (furnace), open ones with boundaries (Cornell box, disk).
std::vector<SurfaceScene> walk_scenes() {
  std::vector<SurfaceScene> scenes;
  scenes.push_back(make_furnace(0.5, 1.0, 1));
  scenes.push_back(make_cornell_box());
  scenes.push_back(make_surface_scene(test::make_disk(3, 0.3)));
  return scenes;
}

TEST(HtexWalk, SingleStepsReverseExactly) {
  // From every valid texel along every axis direction: the step, then the step back along the
  // turned direction's opposite, returns to the start; and the step lands on a valid texel.
  for (const SurfaceScene& scene : walk_scenes()) {
    size_t steps = 0, crossings = 0, failed = 0;
    for (const SceneMesh& m : scene.meshes) {
      const HalfedgeMesh mesh = build_halfedge_mesh(m);
      for (uint32_t n : {2u, 4u}) {
        for (uint32_t e = 0; e < mesh.edge_count(); ++e)
          for (int32_t j = 0; j < int32_t(n); ++j)
            for (int32_t i = 0; i < int32_t(n); ++i) {
              const htex::QuadTexel t{e, i, j};
              if (htex::is_ghost_texel(mesh, n, t)) continue;
              for (const glm::ivec2 d : {glm::ivec2(1, 0), glm::ivec2(-1, 0), glm::ivec2(0, 1), glm::ivec2(0, -1)}) {
                const auto s = htex::step_texel(mesh, n, t, d);
                if (!s) {
                  ++failed;
                  continue;
                }
                ++steps;
                if (s->texel.edge != e) ++crossings;
                EXPECT_GE(s->texel.i, 0);
                EXPECT_GE(s->texel.j, 0);
                EXPECT_LT(s->texel.i, int32_t(n));
                EXPECT_LT(s->texel.j, int32_t(n));
                EXPECT_FALSE(htex::is_ghost_texel(mesh, n, s->texel));
                const glm::ivec2 back = -s->turn(d);
                ASSERT_EQ(std::abs(back.x) + std::abs(back.y), 1);
                const auto r = htex::step_texel(mesh, n, s->texel, back);
                ASSERT_TRUE(r.has_value()) << scene.name << " edge " << e << " (" << i << "," << j << ")";
                EXPECT_EQ(r->texel, t) << scene.name << " edge " << e << " (" << i << "," << j << ") dir " << d.x << "," << d.y;
                EXPECT_EQ(r->turn(s->turn(d)), d);  // the direction turns back too
              }
            }
      }
    }
    EXPECT_GT(crossings, steps / 4) << scene.name;  // most of these quads are small: many steps cross
    if (scene.name.rfind("furnace", 0) == 0) {
      EXPECT_EQ(failed, 0u) << "a closed surface has no edge to fall off";
    }
    std::printf("%s: %zu steps (%zu into another quad), %zu off the surface\n", scene.name.c_str(), steps, crossings, failed);
  }
}

// The largest distance between a sample and a table neighbour, in units of the bound
// (|di| + |dj| + sqrt(2)) * stretch / n: each unit step moves the texel centre by at most one
// texel of the charts it joins (stretch / n, the quads' largest stretch), and snapping a vertex
// corner texel to its vertex moves it by at most sqrt(2)/2 texel at either end.
double worst_neighbour_ratio(const SurfaceScene& scene, const GiDenseSet& set, size_t& valid, size_t& total) {
  std::vector<double> stretch(scene.meshes.size(), 0.0);
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const HalfedgeMesh mesh = build_halfedge_mesh(scene.meshes[m]);
    for (uint32_t e = 0; e < mesh.edge_count(); ++e) stretch[m] = std::max(stretch[m], htex::quad_stretch(mesh, e));
  }
  double worst = 0.0;
  valid = total = 0;
  for (size_t k = 0; k < set.samples.size(); ++k)
    for (uint32_t c = 0; c < set.table_width; ++c) {
      ++total;
      const uint32_t n = set.neighbours[k * set.table_width + c];
      if (n == kNoNeighbour) continue;
      ++valid;
      const auto& a = set.samples[k];
      const auto& b = set.samples[n];
      EXPECT_EQ(a.mesh, b.mesh);  // the walk stays on its mesh
      const glm::ivec2 o = set.offsets[c];
      const double bound = (std::abs(o.x) + std::abs(o.y) + std::sqrt(2.0)) * stretch[a.mesh] / a.side;
      worst = std::max(worst, glm::length(a.position - b.position) / bound);
    }
  return worst;
}

TEST(GiDenseSet, SamplesAreTheNonGhostTexelsWhereHtexShadesThem) {
  const SurfaceScene scene = make_cornell_box();
  const GiDenseSet set = surface::build_gi_dense_set(scene, {.texels_per_unit = 0.01, .level = 0, .max_radius = 2});
  std::vector<HalfedgeMesh> meshes;
  for (const SceneMesh& m : scene.meshes) meshes.push_back(build_halfedge_mesh(m));
  size_t expected = 0;
  uint32_t first = 0;
  std::vector<uint32_t> first_of_mesh;
  for (const SceneMesh& m : scene.meshes) {
    first_of_mesh.push_back(first);
    first += static_cast<uint32_t>(m.triangles.size());
  }
  for (const auto& s : set.samples) {
    const htex::TexelPoint tp = htex::texel_point(meshes[s.mesh], s.edge, s.side, s.i, s.j);
    EXPECT_FALSE(tp.ghost);
    EXPECT_EQ(glm::length(tp.position - s.position), 0.0);
    EXPECT_EQ(s.global_triangle, first_of_mesh[s.mesh] + s.triangle);
    const auto& tri = scene.meshes[s.mesh].triangles[s.triangle];
    const auto& p = scene.meshes[s.mesh].positions;
    const glm::dvec3 from_bary = s.bary.x * p[tri[0]] + s.bary.y * p[tri[1]] + s.bary.z * p[tri[2]];
    EXPECT_LT(glm::length(from_bary - s.position), 1e-9 * 600.0);
    EXPECT_NEAR(glm::length(s.viewer), 1.0, 1e-12);
  }
  // Every non-ghost texel is there: per quad, n^2 texels, or the n (n + 1) / 2 of the half
  // quad on a boundary edge.
  for (size_t m = 0; m < meshes.size(); ++m) {
    uint32_t side = 0;
    for (const auto& s : set.samples)
      if (s.mesh == m) side = s.side;
    ASSERT_GE(side, 2u);
    for (uint32_t e = 0; e < meshes[m].edge_count(); ++e)
      expected += meshes[m].twin[meshes[m].edge_halfedge[e]] == kNoHalfedge ? side * (side + 1) / 2 : side * side;
  }
  EXPECT_EQ(set.samples.size(), expected);
  std::printf("Cornell box dense set: %zu samples\n", set.samples.size());
}

TEST(GiDenseSet, NeighboursAcrossEdgesAreGeometricallyClose) {
  for (const SurfaceScene& scene : walk_scenes()) {
    const double density = scene.name == "cornell-box" ? 0.03 : 16.0;  // quads of 8 to 16 texels
    const GiDenseSet set = surface::build_gi_dense_set(scene, {.texels_per_unit = density, .level = 0, .max_radius = 2});
    ASSERT_EQ(set.table_width, 24u);
    size_t valid = 0, total = 0;
    const double worst = worst_neighbour_ratio(scene, set, valid, total);
    EXPECT_LE(worst, 1.0) << scene.name;
    EXPECT_GT(valid, total / 2) << scene.name;  // the table is mostly full: the bound is not vacuous
    // Walks that cross into other quads are there and obey the bound too.
    size_t other_quad = 0;
    for (size_t k = 0; k < set.samples.size(); ++k)
      for (uint32_t c = 0; c < set.table_width; ++c) {
        const uint32_t n = set.neighbours[k * set.table_width + c];
        if (n != kNoNeighbour && set.samples[n].edge != set.samples[k].edge) ++other_quad;
      }
    // (a tenth at least: with quads of up to 16 texels, a radius-2 walk leaves its quad only
    // from the texels within 2 of its border)
    EXPECT_GT(other_quad, valid / 10) << scene.name;
    std::printf("%s: %zu samples, %zu of %zu table entries valid (%zu in another quad), worst distance %.3f of the bound\n",
                scene.name.c_str(), set.samples.size(), valid, total, other_quad, worst);
  }
}

TEST(GiDenseSet, WalkOnAFlatDiskMatchesTheTexelGrid) {
  // On a flat mesh the charts of neighbouring faces are coplanar: a one-texel step crosses
  // quad borders with a jump of at most one texel of either chart; two steps along an axis
  // and back return to the start.
  const SurfaceScene scene = make_surface_scene(test::make_disk(2, 0.0));
  const HalfedgeMesh mesh = build_halfedge_mesh(scene.meshes[0]);
  const uint32_t n = 4;
  size_t checked = 0;
  for (uint32_t e = 0; e < mesh.edge_count(); ++e)
    for (int32_t j = 0; j < int32_t(n); ++j)
      for (int32_t i = 0; i < int32_t(n); ++i) {
        const htex::QuadTexel t{e, i, j};
        if (htex::is_ghost_texel(mesh, n, t)) continue;
        for (const glm::ivec2 d : {glm::ivec2(1, 0), glm::ivec2(0, 1)}) {
          const auto there = htex::walk_texel(mesh, n, t, 2 * d);
          if (!there) continue;
          // Back: the same two steps with the direction as it arrived, reversed.
          auto s1 = htex::step_texel(mesh, n, t, d);
          ASSERT_TRUE(s1);
          auto s2 = htex::step_texel(mesh, n, s1->texel, s1->turn(d));
          ASSERT_TRUE(s2);
          EXPECT_EQ(s2->texel, *there);
          const glm::ivec2 back = -s2->turn(s1->turn(d));
          auto b1 = htex::step_texel(mesh, n, *there, back);
          ASSERT_TRUE(b1);
          auto b2 = htex::step_texel(mesh, n, b1->texel, b1->turn(back));
          ASSERT_TRUE(b2);
          EXPECT_EQ(b2->texel, t);
          ++checked;
        }
      }
  EXPECT_GT(checked, 100u);
}

TEST(GiDenseSet, StepRejectsDiagonalDirections) {
  const HalfedgeMesh mesh = build_halfedge_mesh(make_furnace(0.5, 1.0, 0).meshes[0]);
  EXPECT_THROW(htex::step_texel(mesh, 4, {0, 1, 1}, {1, 1}), std::invalid_argument);
  EXPECT_THROW(htex::step_texel(mesh, 4, {0, 1, 1}, {0, 0}), std::invalid_argument);
}

// ---- radiance leaving surface points (the CPU reference of GI) --------------------------------

std::vector<reference::SurfacePointQuery> furnace_points(const SurfaceScene& scene, size_t count) {
  std::vector<reference::SurfacePointQuery> q;
  const SceneMesh& m = scene.meshes[0];
  for (size_t k = 0; k < count; ++k) {
    const uint32_t t = static_cast<uint32_t>((k * 7) % m.triangles.size());
    const auto& tri = m.triangles[t];
    const glm::dvec3 n = glm::normalize(glm::cross(m.positions[tri[1]] - m.positions[tri[0]], m.positions[tri[2]] - m.positions[tri[0]]));
    q.push_back({0, t, 0.2 + 0.05 * double(k % 5), 0.3, n});
  }
  return q;
}

TEST(RadianceLeaving, FurnaceGivesEmissionDirectAndOneBounce) {
  // Albedo A, emission Le: a point's radiance after at most 2 reflections is Le (1 + A + A^2);
  // the one-bounce part alone (min_bounces = max_bounces = 2) is A^2 Le, the GI target.
  const double A = 0.5, Le = 1.5;
  const SurfaceScene scene = make_furnace(A, Le, 1);
  const auto points = furnace_points(scene, 24);
  reference::PathTracerSettings s;
  s.samples_per_pixel = 256;
  s.max_bounces = 2;
  s.roulette_after = 2;
  s.seed = 5;
  reference::PathTracerCounts counts;
  const auto all = reference::radiance_leaving(scene, points, s, &counts);
  EXPECT_EQ(counts.paths, points.size() * 256);
  EXPECT_EQ(counts.non_finite, 0u);
  s.min_bounces = 2;
  const auto bounce = reference::radiance_leaving(scene, points, s);
  double worst_all = 0.0, worst_bounce = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    const double se_all = all[i].standard_error().y, se_bounce = bounce[i].standard_error().y;
    ASSERT_GT(se_all, 0.0);
    ASSERT_GT(se_bounce, 0.0);
    EXPECT_NEAR(all[i].mean.y, Le * (1 + A + A * A), 5.0 * se_all);
    EXPECT_NEAR(bounce[i].mean.y, A * A * Le, 5.0 * se_bounce);
    worst_all = std::max(worst_all, std::abs(all[i].mean.y - Le * (1 + A + A * A)) / se_all);
    worst_bounce = std::max(worst_bounce, std::abs(bounce[i].mean.y - A * A * Le) / se_bounce);
  }
  // Without bounces: exactly the emission (seen from the front).
  s.min_bounces = 0;
  s.max_bounces = 0;
  const auto emitted = reference::radiance_leaving(scene, points, s);
  for (const auto& r : emitted) EXPECT_EQ(r.mean, glm::dvec3(Le));
  std::printf("radiance leaving furnace points: worst %.2f se (all), %.2f se (one bounce)\n", worst_all, worst_bounce);
}

TEST(RadianceLeaving, BadPointsAreInputErrors) {
  const SurfaceScene scene = make_furnace(0.5, 1.0, 0);
  reference::PathTracerSettings s;
  s.samples_per_pixel = 1;
  std::vector<reference::SurfacePointQuery> q = {{1, 0, 0.3, 0.3, {0, 0, 1}}};
  EXPECT_THROW(reference::radiance_leaving(scene, q, s), InputError);
  q = {{0, 9999, 0.3, 0.3, {0, 0, 1}}};
  EXPECT_THROW(reference::radiance_leaving(scene, q, s), InputError);
  q = {{0, 0, 0.3, 0.3, {0, 0, 0}}};
  EXPECT_THROW(reference::radiance_leaving(scene, q, s), InputError);
  q = {{0, 0, 0.3, 0.3, {0, 0, 1}}};
  s.samples_per_pixel = 0;
  EXPECT_THROW(reference::radiance_leaving(scene, q, s), InputError);
}

}  // namespace
}  // namespace prismoid
