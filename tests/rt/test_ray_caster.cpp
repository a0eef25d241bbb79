// The ray-tracing foundation (renderer/rt) against the CPU double-precision reference
// (renderer/reference/triangle_bvh.hpp, first_hits): acceleration structures, the shader
// binding table, primary rays and shadow rays, on lavapipe with validation on.
//
// Tolerances. The GPU traces floats relative to the scene origin; the reference traces doubles.
// With u = 2^-24 (float unit roundoff), R = the largest |vertex - origin|, o = |ray origin -
// origin| and t the distance along the ray, the float ray differs from the exact one by at most
//   - vertex rounding: each corner moves by <= sqrt(3) u R, so a plane moves by that much;
//   - ray-origin rounding: <= sqrt(3) u o;
//   - direction: the float camera frame (rounded from double) combined and normalized in a few
//     operations, ~8 u relative, i.e. <= 8 u t sideways at distance t;
//   - the intersection arithmetic (implementation-defined, a float watertight test shears and
//     subtracts coordinates of size R + o + t in ~4 operations): ~6 u (R + o + t),
// in all below 16 u (R + o + t). We allow twice that, kSlack = 32:
//     delta(t) = 32 u (R + o + t).
// A ray passing farther than delta from every triangle edge (of the whole scene, up to its hit)
// crosses the same triangles in float as in double, so its hit triangle must be the
// reference's; pixels whose ray passes within delta of an edge are left out of the identity
// comparison (they are counted, and must stay a small fraction). On the hit triangle the hit
// point moves along the ray by at most delta / |cos theta| (theta between ray and normal):
// the distance tolerance; and within the plane by as much, so a barycentric weight moves by at
// most delta / (|cos theta| h_min), h_min the triangle's smallest altitude.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/geometric.hpp>

#include "renderer/reference/path_tracer.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/reference/triangle_bvh.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/rt/ray_caster.hpp"
#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

constexpr double kU = 0x1p-24;
constexpr double kSlack = 32.0;

class RayCasterTest : public test::GpuTest {
 protected:
  void SetUp() override {
    test::GpuTest::SetUp();
    if (!device().ray_tracing_enabled()) GTEST_SKIP() << device().capabilities().name << " has no ray-tracing pipelines";
  }
};

// ---- geometry helpers (double) --------------------------------------------------------------

bool degenerate(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  return glm::length(glm::cross(b - a, c - a)) == 0.0;
}

double point_segment_distance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = b - a;
  const double len2 = glm::dot(d, d);
  const double s = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + s * d));
}

// The distance between segments [p0, p1] and [q0, q1]: closest points of the two lines, clamped
// to the segments, and the four endpoint distances (which cover near-parallel segments).
double segment_distance(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& q0, const glm::dvec3& q1) {
  const glm::dvec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = glm::dot(d1, d1), e = glm::dot(d2, d2), b = glm::dot(d1, d2), c = glm::dot(d1, r), f = glm::dot(d2, r);
  double best = std::min({point_segment_distance(p0, q0, q1), point_segment_distance(p1, q0, q1),
                          point_segment_distance(q0, p0, p1), point_segment_distance(q1, p0, p1)});
  const double denom = a * e - b * b;
  if (a > 0.0 && e > 0.0 && denom > 0.0) {
    const double s = std::clamp((b * f - c * e) / denom, 0.0, 1.0);
    const double t = std::clamp((b * s + f) / e, 0.0, 1.0);
    const double s2 = std::clamp((b * t - c) / a, 0.0, 1.0);
    best = std::min(best, glm::length((p0 + s2 * d1) - (q0 + t * d2)));
  }
  return best;
}

struct Edge {
  glm::dvec3 a, b;
};
std::vector<Edge> edges_of(const SurfaceScene& scene) {
  std::vector<Edge> edges;
  for (const auto& mesh : scene.meshes)
    for (const auto& t : mesh.triangles) {
      const glm::dvec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
      if (degenerate(a, b, c)) continue;
      edges.push_back({a, b});
      edges.push_back({b, c});
      edges.push_back({c, a});
    }
  return edges;
}

double nearest_edge(const std::vector<Edge>& edges, const glm::dvec3& p0, const glm::dvec3& p1) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& e : edges) best = std::min(best, segment_distance(p0, p1, e.a, e.b));
  return best;
}

double local_radius(const SurfaceScene& scene, const glm::dvec3& origin) {
  double r = 0.0;
  for (const auto& mesh : scene.meshes)
    for (const auto& p : mesh.positions) r = std::max(r, glm::length(p - origin));
  return r;
}

// The scene moved by `offset` (positions and camera).
SurfaceScene translated(SurfaceScene s, const glm::dvec3& offset) {
  for (auto& mesh : s.meshes)
    for (auto& p : mesh.positions) p += offset;
  s.camera.eye += offset;
  s.camera.target += offset;
  for (auto& l : s.point_lights) l.position += offset;
  return s;
}

// ---- primary rays against first_hits -------------------------------------------------------

struct PrimaryComparison {
  size_t pixels = 0, compared = 0, near_edge = 0, hits = 0;
  size_t id_mismatches = 0, hit_mismatches = 0, t_out_of_tolerance = 0, b_out_of_tolerance = 0, non_finite = 0;
  double worst_t_ratio = 0.0;  // |t_gpu - t_cpu| / tolerance, largest over compared hits
  double worst_b_ratio = 0.0;
  double worst_relative_t = 0.0;  // |t_gpu - t_cpu| / t_cpu
  void print(const char* what) const {
    std::printf("[ %s ] %zu pixels: %zu compared (%zu hits), %zu within delta of an edge; mismatches: id %zu, hit/miss %zu, "
                "t %zu, b %zu, non-finite %zu; worst |dt|/tol %.3g, |db|/tol %.3g, |dt|/t %.3g\n",
                what, pixels, compared, hits, near_edge, id_mismatches, hit_mismatches, t_out_of_tolerance, b_out_of_tolerance,
                non_finite, worst_t_ratio, worst_b_ratio, worst_relative_t);
  }
};

PrimaryComparison compare_primary(const std::vector<rt::RayHit>& gpu, const SurfaceScene& scene, const glm::dvec3& origin,
                                  uint32_t width, uint32_t height) {
  const Camera& cam = scene.camera;
  const glm::dvec3 forward = glm::normalize(cam.target - cam.eye);
  std::vector<reference::SurfaceRay> rays(size_t(width) * height);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      auto& r = rays[size_t(y) * width + x];
      r.origin = cam.eye;
      r.direction = reference::ray_direction(cam, width, height, x + 0.5, y + 0.5);
      r.t_min = cam.near_distance / glm::dot(r.direction, forward);
    }
  const std::vector<reference::SurfaceHit> cpu = reference::first_hits(scene, rays);
  const std::vector<Edge> edges = edges_of(scene);
  const double R = local_radius(scene, origin), o = glm::length(cam.eye - origin);
  const double t_far = o + R;  // beyond every triangle
  PrimaryComparison c;
  c.pixels = rays.size();
  for (size_t i = 0; i < rays.size(); ++i) {
    const rt::RayHit& g = gpu[i];
    if (!std::isfinite(g.t) || !std::isfinite(g.b1) || !std::isfinite(g.b2)) ++c.non_finite;
    const auto& r = rays[i];
    const reference::SurfaceHit& h = cpu[i];
    const double t_end = h.hit ? h.t : t_far;
    const double delta = kSlack * kU * (R + o + t_end);
    if (nearest_edge(edges, r.origin + r.t_min * r.direction, r.origin + (t_end + delta) * r.direction) <= delta) {
      ++c.near_edge;
      continue;
    }
    ++c.compared;
    if (g.hit != h.hit) {
      ++c.hit_mismatches;
      continue;
    }
    if (!h.hit) continue;
    ++c.hits;
    if (g.mesh != h.mesh || g.triangle != h.triangle) {
      ++c.id_mismatches;
      continue;
    }
    const double cos_theta = std::abs(glm::dot(r.direction, h.normal));
    const double t_tol = delta / cos_theta;
    const double dt = std::abs(double(g.t) - h.t);
    c.worst_t_ratio = std::max(c.worst_t_ratio, dt / t_tol);
    c.worst_relative_t = std::max(c.worst_relative_t, dt / h.t);
    if (dt > t_tol) ++c.t_out_of_tolerance;
    // Barycentrics of the reference hit on its triangle, and the triangle's smallest altitude.
    const SceneMesh& mesh = scene.meshes[h.mesh];
    const auto& tri = mesh.triangles[h.triangle];
    const glm::dvec3 &v0 = mesh.positions[tri[0]], &v1 = mesh.positions[tri[1]], &v2 = mesh.positions[tri[2]];
    reference::TriangleHit exact;
    EXPECT_TRUE(reference::intersect_triangle(v0, v1, v2, r.origin, r.direction, r.t_min,
                                              std::numeric_limits<double>::infinity(), exact));
    const double twice_area = glm::length(glm::cross(v1 - v0, v2 - v0));
    const double longest = std::max({glm::length(v1 - v0), glm::length(v2 - v1), glm::length(v0 - v2)});
    const double b_tol = t_tol / (twice_area / longest);
    const double db = std::max(std::abs(double(g.b1) - exact.b1), std::abs(double(g.b2) - exact.b2));
    c.worst_b_ratio = std::max(c.worst_b_ratio, db / b_tol);
    if (db > b_tol) ++c.b_out_of_tolerance;
  }
  return c;
}

void expect_agreement(const PrimaryComparison& c) {
  EXPECT_EQ(c.non_finite, 0u);
  EXPECT_EQ(c.hit_mismatches, 0u);
  EXPECT_EQ(c.id_mismatches, 0u);
  EXPECT_EQ(c.t_out_of_tolerance, 0u);
  EXPECT_EQ(c.b_out_of_tolerance, 0u);
  // The exclusion must leave a real comparison: edges cover a thin band of pixels only.
  EXPECT_LT(c.near_edge, c.pixels / 20) << "too many pixels near edges for the comparison to mean much";
}

PrimaryComparison cast_and_compare(const vk::Device& device, const SurfaceScene& scene, uint32_t width, uint32_t height,
                                   const rt::AccelBuildOptions& options = {}) {
  const rt::SceneAccel accel(device, scene, options);
  const rt::RayCaster caster(device, accel);
  return compare_primary(caster.primary_hits(scene.camera, width, height), scene, accel.origin(), width, height);
}

// ---- tests ---------------------------------------------------------------------------------

TEST(ShaderBindingTable, LavapipeLayout) {
  // lavapipe: handle 32, handle alignment 16, base alignment 32.
  const rt::SbtLayout l = rt::layout_shader_binding_table({32, 16, 32}, 2, 2, 1);
  EXPECT_EQ(l.raygen.offset, 0u);
  EXPECT_EQ(l.raygen.stride, 32u);
  EXPECT_EQ(l.raygen.size, 64u);
  EXPECT_EQ(l.miss.offset, 64u);
  EXPECT_EQ(l.miss.stride, 32u);
  EXPECT_EQ(l.miss.size, 64u);
  EXPECT_EQ(l.hit.offset, 128u);
  EXPECT_EQ(l.hit.stride, 32u);
  EXPECT_EQ(l.hit.size, 32u);
  EXPECT_EQ(l.bytes, 160u);
}

TEST(ShaderBindingTable, NvidiaLayout) {
  // NVIDIA (RTX and Hopper drivers): handle 32, handle alignment 32, base alignment 64. Each
  // ray-generation record starts a region, so it is 64 apart; miss and hit records 32.
  const rt::SbtLayout l = rt::layout_shader_binding_table({32, 32, 64}, 2, 2, 1);
  EXPECT_EQ(l.raygen.offset, 0u);
  EXPECT_EQ(l.raygen.stride, 64u);
  EXPECT_EQ(l.raygen.size, 128u);
  EXPECT_EQ(l.miss.offset, 128u);
  EXPECT_EQ(l.miss.stride, 32u);
  EXPECT_EQ(l.miss.size, 64u);
  EXPECT_EQ(l.hit.offset, 192u);
  EXPECT_EQ(l.hit.stride, 32u);
  EXPECT_EQ(l.bytes, 224u);
}

TEST(ShaderBindingTable, RulesHoldForOddProperties) {
  for (const rt::ShaderGroupProperties p : {rt::ShaderGroupProperties{20, 8, 64}, rt::ShaderGroupProperties{32, 64, 16},
                                            rt::ShaderGroupProperties{48, 16, 256}}) {
    for (uint32_t n : {1u, 3u, 7u}) {
      const rt::SbtLayout l = rt::layout_shader_binding_table(p, n, n + 1, n + 2);
      const rt::SbtRegion* regions[] = {&l.raygen, &l.miss, &l.hit};
      VkDeviceSize end = 0;
      for (const rt::SbtRegion* r : regions) {
        EXPECT_EQ(r->offset % p.base_alignment, 0u);
        EXPECT_EQ(r->stride % p.handle_alignment, 0u);
        EXPECT_GE(r->stride, p.handle_size);
        EXPECT_GE(r->offset, end) << "regions overlap";
        EXPECT_EQ(r->size, r->stride * r->records);
        end = r->offset + r->size;
      }
      EXPECT_EQ(l.raygen.stride % p.base_alignment, 0u) << "each raygen record must be able to start a region";
      EXPECT_EQ(l.bytes, end);
    }
  }
  EXPECT_THROW(rt::layout_shader_binding_table({32, 24, 64}, 1, 1, 1), std::invalid_argument);
  EXPECT_THROW(rt::layout_shader_binding_table({32, 16, 32}, 0, 1, 1), std::invalid_argument);
}

TEST_F(RayCasterTest, DeviceEnablesRayTracingWithItsTableProperties) {
  const auto& caps = device().capabilities();
  EXPECT_TRUE(caps.ray_tracing());
  EXPECT_GT(caps.shader_group_handle_size, 0u);
  EXPECT_GT(caps.shader_group_base_alignment, 0u);
  EXPECT_GT(caps.min_acceleration_structure_scratch_alignment, 0u);
  std::printf("[ device ] %s: shader group handle %u B, alignment %u, base alignment %u, scratch alignment %u\n",
              caps.name.c_str(), caps.shader_group_handle_size, caps.shader_group_handle_alignment,
              caps.shader_group_base_alignment, caps.min_acceleration_structure_scratch_alignment);
}

TEST_F(RayCasterTest, CornellBoxPrimaryHitsMatchTheReference) {
  const SurfaceScene scene = make_cornell_box();
  const PrimaryComparison c = cast_and_compare(device(), scene, 200, 200);
  c.print("cornell box");
  expect_agreement(c);
  EXPECT_GT(c.hits, c.pixels / 2);
}

TEST_F(RayCasterTest, CornellBoxFarFromTheOriginMatchesTheReference) {
  const SurfaceScene scene = translated(make_cornell_box(), glm::dvec3(1e6, -1e6, 1e6));
  const rt::SceneAccel accel(device(), scene);
  EXPECT_NEAR(accel.origin().x, 1e6 + 278.0, 1.0);
  const rt::RayCaster caster(device(), accel);
  const PrimaryComparison c = compare_primary(caster.primary_hits(scene.camera, 200, 200), scene, accel.origin(), 200, 200);
  c.print("cornell box at 1e6");
  expect_agreement(c);
  EXPECT_GT(c.hits, c.pixels / 2);
}

TEST_F(RayCasterTest, WithoutTheOriginShiftFarScenesFailTheSameTolerance) {
  // The control: the same scene traced with floats relative to the world origin (ulp at 1e6 is
  // 1/16) misses the distance tolerance on many pixels, so the comparison above has teeth.
  const SurfaceScene scene = translated(make_cornell_box(), glm::dvec3(1e6, -1e6, 1e6));
  rt::AccelBuildOptions options;
  options.origin = glm::dvec3(0.0);
  const rt::SceneAccel accel(device(), scene, options);
  const rt::RayCaster caster(device(), accel);
  // The tolerance of the shifted case (R and o measured from the scene's own centre).
  const PrimaryComparison c =
      compare_primary(caster.primary_hits(scene.camera, 100, 100), scene, bounds_of(scene).center(), 100, 100);
  c.print("cornell box at 1e6, no origin shift");
  EXPECT_GT(c.t_out_of_tolerance + c.id_mismatches + c.hit_mismatches, c.hits / 4);
}

TEST_F(RayCasterTest, CompactionKeepsEveryHit) {
  const SurfaceScene scene = make_cornell_box();
  rt::AccelBuildOptions plain;
  plain.compact = false;
  const rt::SceneAccel a(device(), scene, plain), b(device(), scene);
  EXPECT_EQ(a.stats().blas_bytes, a.stats().blas_bytes_built);
  EXPECT_LE(b.stats().blas_bytes, b.stats().blas_bytes_built);
  std::printf("[ compaction ] BLAS bytes %llu built, %llu compacted\n", static_cast<unsigned long long>(b.stats().blas_bytes_built),
              static_cast<unsigned long long>(b.stats().blas_bytes));
  const auto ha = rt::RayCaster(device(), a).primary_hits(scene.camera, 96, 96);
  const auto hb = rt::RayCaster(device(), b).primary_hits(scene.camera, 96, 96);
  size_t same = 0;
  for (size_t i = 0; i < ha.size(); ++i)
    if (ha[i].hit == hb[i].hit && ha[i].mesh == hb[i].mesh && ha[i].triangle == hb[i].triangle && ha[i].t == hb[i].t) ++same;
  EXPECT_EQ(same, ha.size());
}

TEST_F(RayCasterTest, DegenerateTrianglesAreNeverHitAndBreakNothing) {
  SurfaceScene scene = make_cornell_box();
  // Zero-area triangles inside the floor mesh (so later triangle indices shift past them) and a
  // mesh of nothing else across the middle of the view, on the eye's own height: with an odd
  // image height the middle row's rays (direction.y == 0 exactly) run along its line.
  SceneMesh& floor = scene.meshes[0];
  const auto f = static_cast<uint32_t>(floor.positions.size());
  floor.positions.push_back({100.0, 0.0, 100.0});
  floor.positions.push_back({200.0, 0.0, 200.0});
  floor.positions.push_back({300.0, 0.0, 300.0});  // collinear with the two before
  floor.triangles.insert(floor.triangles.begin(), {f, f + 1, f + 2});
  floor.triangles.insert(floor.triangles.begin() + 2, {f, f, f + 1});
  // In every other mesh, a zero-area triangle before each triangle (triangle j moves to 2j + 1).
  uint32_t interleaved = 0;
  for (size_t m = 1; m < scene.meshes.size(); ++m) {
    std::vector<std::array<uint32_t, 3>> triangles;
    for (const auto& t : scene.meshes[m].triangles) {
      triangles.push_back({t[0], t[0], t[1]});
      triangles.push_back(t);
      ++interleaved;
    }
    scene.meshes[m].triangles = triangles;
  }
  SceneMesh line;
  line.name = "degenerate";
  line.positions = {{-100.0, 273.0, 100.0}, {278.0, 273.0, 100.0}, {656.0, 273.0, 100.0}, {278.0, 273.0, 100.0}};
  line.triangles = {{0, 1, 2}, {0, 1, 3}, {1, 3, 1}, {2, 2, 2}};
  scene.meshes.push_back(line);
  scene.camera.eye.y = scene.camera.target.y = 273.0;

  const rt::SceneAccel accel(device(), scene);
  EXPECT_EQ(accel.stats().degenerate_triangles, 6u + interleaved);
  EXPECT_EQ(accel.instance_count(), scene.meshes.size() - 1) << "a mesh of degenerate triangles only needs no instance";
  const rt::RayCaster caster(device(), accel);
  const uint32_t width = 120, height = 121;
  const std::vector<rt::RayHit> hits = caster.primary_hits(scene.camera, width, height);
  for (const auto& h : hits) {
    if (!h.hit) continue;
    EXPECT_NE(h.mesh, scene.meshes.size() - 1) << "a degenerate triangle was hit";
    if (h.mesh == 0) {
      EXPECT_TRUE(h.triangle != 0 && h.triangle != 2) << "a degenerate floor triangle was hit";
    } else {
      EXPECT_EQ(h.triangle % 2, 1u) << "a degenerate triangle of mesh " << h.mesh << " was hit";
    }
  }
  const PrimaryComparison c = compare_primary(hits, scene, accel.origin(), width, height);
  c.print("cornell box with degenerate triangles");
  expect_agreement(c);
  // The shadow raygen sees them as nothing too: a segment through the line's middle is free.
  const rt::ShadowSegment through{{278.0, 200.0, 100.0}, {278.0, 350.0, 100.0}};
  EXPECT_EQ(caster.visibility(std::span(&through, 1)), std::vector<uint8_t>{1});
}

TEST_F(RayCasterTest, EmptyScenesGiveOnlyMisses) {
  SurfaceScene empty;
  empty.camera = make_cornell_box().camera;
  SurfaceScene no_triangles = empty;
  no_triangles.materials = {default_surface_material()};
  no_triangles.meshes.push_back({});
  no_triangles.meshes.back().positions = {{0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}};
  for (const SurfaceScene* scene : {&empty, &no_triangles}) {
    const rt::SceneAccel accel(device(), *scene);
    EXPECT_EQ(accel.instance_count(), 0u);
    const rt::RayCaster caster(device(), accel);
    const auto hits = caster.primary_hits(scene->camera, 32, 24);
    ASSERT_EQ(hits.size(), 32u * 24u);
    for (const auto& h : hits) {
      EXPECT_FALSE(h.hit);
      EXPECT_EQ(h.t, -1.0f);
    }
    const glm::dvec3 points[] = {{0.0, 0.0, 0.0}, {5.0, 1.0, 2.0}};
    EXPECT_EQ(caster.point_light_visibility(points, {0.0, 10.0, 0.0}, 1e-3), (std::vector<uint8_t>{1, 1}));
  }
}

// ---- shadow rays against TriangleBvh::occluded ---------------------------------------------

struct ShadowComparison {
  size_t points = 0, near_edge = 0, visible = 0, occluded = 0, mismatches = 0;
};

ShadowComparison compare_floor_shadows(const vk::Device& device, const SurfaceScene& scene, const glm::dvec3& offset) {
  // A grid of points on the floor quad (the box's floor, corners in the generator's order).
  const glm::dvec3 c00 = glm::dvec3(552.8, 0.0, 0.0) + offset, c10 = glm::dvec3(0.0, 0.0, 0.0) + offset;
  const glm::dvec3 c11 = glm::dvec3(0.0, 0.0, 559.2) + offset, c01 = glm::dvec3(549.6, 0.0, 559.2) + offset;
  // The point light: 1 mm below the centre of the ceiling light.
  const glm::dvec3 light = glm::dvec3(278.0, 548.8 - kCornellLightDrop - 1.0, 279.5) + offset;
  const double spawn = 0.05;  // mm skipped at both ends (> delta / sin of the steepest angle to the floor)
  const int n = 160;
  std::vector<glm::dvec3> points;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double s = (i + 0.5) / n, t = (j + 0.5) / n;
      points.push_back((1 - s) * (1 - t) * c00 + s * (1 - t) * c10 + s * t * c11 + (1 - s) * t * c01);
    }
  const rt::SceneAccel accel(device, scene);
  const std::vector<uint8_t> gpu = rt::RayCaster(device, accel).point_light_visibility(points, light, spawn);

  std::vector<reference::TriangleBvh::Triangle> triangles;
  for (const auto& mesh : scene.meshes)
    for (const auto& t : mesh.triangles) triangles.push_back({mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]});
  const reference::TriangleBvh bvh(std::move(triangles));
  const std::vector<Edge> edges = edges_of(scene);
  const double R = local_radius(scene, accel.origin());
  ShadowComparison c;
  c.points = points.size();
  for (size_t i = 0; i < points.size(); ++i) {
    const glm::dvec3 d = light - points[i];
    const double len = glm::length(d);
    const double s0 = spawn / len, s1 = 1.0 - spawn / len;
    const bool cpu_visible = !bvh.occluded(points[i], d, s0, s1);
    const double delta = kSlack * kU * (R + glm::length(points[i] - accel.origin()) + len);
    if (nearest_edge(edges, points[i] + s0 * d, points[i] + s1 * d) <= delta) {
      ++c.near_edge;
      continue;
    }
    (cpu_visible ? c.visible : c.occluded) += 1;
    if ((gpu[i] != 0) != cpu_visible) ++c.mismatches;
  }
  return c;
}

TEST_F(RayCasterTest, CeilingLightVisibilityFromTheFloorMatchesTheReference) {
  for (const glm::dvec3 offset : {glm::dvec3(0.0), glm::dvec3(1e6, -1e6, 1e6)}) {
    const ShadowComparison c = compare_floor_shadows(device(), translated(make_cornell_box(), offset), offset);
    std::printf("[ floor shadows, offset %g ] %zu points: %zu visible, %zu occluded, %zu within delta of an edge, %zu mismatches\n",
                offset.x, c.points, c.visible, c.occluded, c.near_edge, c.mismatches);
    EXPECT_EQ(c.mismatches, 0u);
    EXPECT_GT(c.visible, c.points / 4);   // the light reaches most of the floor...
    EXPECT_GT(c.occluded, c.points / 20); // ...and the blocks shadow some of it
    EXPECT_LT(c.near_edge, c.points / 20);
  }
}

TEST_F(RayCasterTest, SegmentsStopWhereTheyAreTold) {
  const SurfaceScene scene = make_cornell_box();
  const rt::SceneAccel accel(device(), scene);
  const rt::RayCaster caster(device(), accel);
  // From the middle of the box towards and through the back wall (z = 559.2).
  const glm::dvec3 from(278.0, 400.0, 500.0), beyond(278.0, 400.0, 600.0);
  const std::vector<rt::ShadowSegment> segments = {
      {from, beyond, 0.0, 1.0},            // crosses the wall
      {from, beyond, 0.0, 0.5},            // stops 9.2 before it
      {from, beyond, 0.7, 1.0},            // starts 9.2 past it
      {from, from, 0.0, 1.0},              // a point
      {beyond, from, 0.0, 0.6},            // from behind the wall, back through it (its back side)
  };
  EXPECT_EQ(caster.visibility(segments), (std::vector<uint8_t>{0, 1, 1, 1, 0}));
  const rt::ShadowSegment bad{from, beyond, 0.5, 0.4};
  EXPECT_THROW(caster.visibility(std::span(&bad, 1)), InputError);
  const rt::ShadowSegment nan{{std::nan(""), 0.0, 0.0}, beyond, 0.0, 1.0};
  EXPECT_THROW(caster.visibility(std::span(&nan, 1)), InputError);
}

TEST_F(RayCasterTest, BadInputIsRefusedClearly) {
  const SurfaceScene scene = make_cornell_box();
  const rt::SceneAccel accel(device(), scene);
  const rt::RayCaster caster(device(), accel);
  EXPECT_THROW(caster.primary_hits(scene.camera, 0, 10), InputError);
  Camera broken = scene.camera;
  broken.target = broken.eye;
  EXPECT_THROW(caster.primary_hits(broken, 10, 10), InputError);
  SurfaceScene bad = scene;
  bad.meshes[0].triangles.push_back({0, 1, 99});
  EXPECT_THROW(rt::SceneAccel(device(), bad), InputError);
}

}  // namespace
}  // namespace prismoid
