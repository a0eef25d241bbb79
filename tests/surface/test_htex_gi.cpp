// ReSTIR GI hosted by the Htex backend (renderer/surface/gi/htex_gi.hpp) on lavapipe with
// validation on: the GLSL texel walk against the C++ one, the furnace against its closed form,
// the Cornell box against the CPU path tracer (max_bounces 2), and the fallback layer at a
// disocclusion. No GPU times are asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <set>

#include "renderer/reference/htex_reference.hpp"
#include "renderer/reference/path_tracer.hpp"
#include "renderer/surface/gi/htex_gi.hpp"
#include "renderer/surface/htex/htex_walk.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/pipeline.hpp"
#include "scene/generators.hpp"
#include "scene/surface_generators.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/htex_fixture.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

using surface::HtexGi;
using surface::RestirGiSettings;

class HtexGiTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    if (!device().ray_tracing_enabled()) GTEST_SKIP() << device().capabilities().name << " has no ray-tracing pipelines";
  }
};

// ---- 1. The GLSL walk is the C++ walk ---------------------------------------------------------

struct WalkQuery {
  glm::uvec4 texel;  // global edge, n, i, j
  glm::ivec4 offset;
};

TEST_F(HtexGiTest, GlslWalkMatchesTheCppWalk) {
  SurfaceScene scene = make_cornell_box();  // open quads: boundary edges and ghost texels
  SceneMesh cube;
  cube.name = "cube";
  const SurfaceMesh c = make_cube_surface(glm::dvec3(0.0, 0.0, 5.0), 0.7, 2);
  cube.positions = c.points;
  cube.triangles = c.triangles;
  scene.meshes.push_back(cube);
  const SurfaceScene sphere = make_furnace(0.5, 1.0, 1);  // closed icosphere: vertices of valence 5 and 6
  scene.meshes.push_back(sphere.meshes[0]);
  htex::LayoutOptions options;
  options.texels_per_unit = 0.05;
  const surface::HtexGeometry g(scene, options);
  const surface::HtexTables tables = surface::upload_htex_tables(device(), g, 1);

  std::mt19937_64 gen(3);
  std::vector<WalkQuery> queries;
  struct Cpu {
    uint32_t mesh, n;
    htex::QuadTexel from;
    glm::ivec2 offset;
  };
  std::vector<Cpu> cpu;
  while (queries.size() < 8000) {
    const uint32_t mesh = uint32_t(gen() % g.meshes.size());
    const HalfedgeMesh& m = g.meshes[mesh];
    const htex::MeshLayout& ml = g.layout.meshes()[mesh];
    const uint32_t n = ml.side(uint32_t(gen() % ml.levels));
    const htex::QuadTexel from{uint32_t(gen() % m.edge_count()), int32_t(gen() % n), int32_t(gen() % n)};
    if (htex::is_ghost_texel(m, n, from)) continue;
    const int r = 1 + int(gen() % 6);
    const glm::ivec2 offset(int(gen() % uint64_t(2 * r + 1)) - r, int(gen() % uint64_t(2 * r + 1)) - r);
    cpu.push_back({mesh, n, from, offset});
    queries.push_back({glm::uvec4(ml.first_quad + from.edge, n, uint32_t(from.i), uint32_t(from.j)), glm::ivec4(offset, 0, 0)});
  }

  const std::vector<glm::ivec4> results = run_htex_twin_shader<glm::ivec4>(device(), tables, "surface/htex/walk_test.comp", queries);
  size_t ok = 0, crossed = 0, mismatches = 0;
  for (size_t k = 0; k < cpu.size(); ++k) {
    const Cpu& q = cpu[k];
    const auto expected = htex::walk_texel(g.meshes[q.mesh], q.n, q.from, q.offset);
    const uint32_t first = g.layout.meshes()[q.mesh].first_quad;
    const glm::ivec4 want = expected ? glm::ivec4(1, int(first + expected->edge), expected->i, expected->j) : glm::ivec4(0);
    if (results[k] != want && ++mismatches <= 5)
      ADD_FAILURE() << "query " << k << ": GPU (" << results[k].x << ", " << results[k].y << ", " << results[k].z << ", " << results[k].w
                    << ") C++ (" << want.x << ", " << want.y << ", " << want.z << ", " << want.w << ")";
    ok += expected.has_value();
    crossed += expected && expected->edge != q.from.edge;
  }
  std::printf("walk: %zu queries, %zu reach a texel (%zu in another quad), %zu leave the surface; %zu mismatches\n", cpu.size(), ok,
              crossed, cpu.size() - ok, mismatches);
  EXPECT_EQ(mismatches, 0u);
  EXPECT_GT(crossed, cpu.size() / 10);        // the walks do cross quad borders
  EXPECT_GT(cpu.size() - ok, cpu.size() / 50);  // and some leave the open quads
}

// ---- A scene with the Htex pass and GI --------------------------------------------------------

surface::HtexSettings gi_htex_settings(uint32_t pages) {
  surface::HtexSettings s;
  s.pool_pages = pages;
  s.indirect = true;
  s.sky_ambient = false;
  return s;
}

struct GiRig {
  HtexRig rig;
  HtexGi gi;
  GiRig(const vk::Device& device, SurfaceScene scene, double texels_per_unit, uint32_t pages, const surface::HtexGiOptions& options = {})
      : rig(device, std::move(scene), htex::LayoutOptions{.texels_per_unit = texels_per_unit}, gi_htex_settings(pages)),
        gi(device, *rig.pass, rig.gpu, rig.accel, options) {}
  surface::HtexGiImage render(const vk::Device& device, const Camera& camera, uint32_t w, uint32_t h, uint32_t frames,
                              const RestirGiSettings& s, uint32_t first = 0, bool keep = false) {
    return surface::render_htex_gi(device, *rig.pass, gi, rig.gpu, rig.accel.tlas(), camera, {w, h}, frames, s, first, keep);
  }
};

bool finite_rgba(const std::vector<float>& v) {
  return std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); });
}

// ---- 2. Furnace -------------------------------------------------------------------------------
// Inside a closed sphere of albedo A and emission Le, emission + direct + one bounce is
// Le (1 + A + A^2) everywhere. Each pixel's mean over the frames is held to it within 5 of its
// own standard errors (from the spread across frames; frames share reservoirs, so their errors
// are correlated and the spread understates the error: hence 5, not 3) plus an allowance for the
// two approximations the GPU makes in this scene: emitter visibility by the ratio over four
// points per emitter, which near concave edges removes light (restir_gi.glsl, test_restir_gi's
// furnace), and the area-light terms at vertex-corner texels on emissive meshes (up to +13%
// at coarse levels, docs/architecture.md): 8% of the exact value.

TEST_F(HtexGiTest, FurnaceConvergesToEmissionDirectAndOneBounce) {
  constexpr double kA = 0.5, kLe = 1.0, kExact = kLe * (1.0 + kA + kA * kA);
  constexpr uint32_t kW = 24, kH = 18, kFrames = 8;
  GiRig g(device(), make_furnace(kA, kLe, 1), 6.0, 64);
  for (const bool unbiased : {false, true}) {
    g.gi.reset();
    g.rig.pass->reset_residency();
    RestirGiSettings s;
    s.unbiased = unbiased;
    const auto out = g.render(device(), g.rig.scene.camera, kW, kH, kFrames, s, 0, true);
    const auto& img = out.image;
    EXPECT_EQ(img.counters.overflow, false);
    size_t covered = 0, outside = 0;
    double sum = 0.0, worst = 0.0;
    for (size_t p = 0; p < size_t(kW) * kH; ++p) {
      if (img.rgba[4 * p + 3] != 1.0f) continue;
      ++covered;
      for (int c = 0; c < 3; ++c) {
        double mean = 0.0, sq = 0.0;
        for (const auto& f : out.frames) {
          ASSERT_TRUE(std::isfinite(f[4 * p + size_t(c)]));
          mean += double(f[4 * p + size_t(c)]) / double(kFrames);
        }
        for (const auto& f : out.frames) sq += (double(f[4 * p + size_t(c)]) - mean) * (double(f[4 * p + size_t(c)]) - mean);
        const double se = std::sqrt(sq / (kFrames - 1) / kFrames);
        const double err = std::abs(mean - kExact);
        worst = std::max(worst, err / kExact);
        if (err > 5.0 * se + 0.08 * kExact) ++outside;
        sum += mean / 3.0;
      }
    }
    std::printf("furnace htex+gi %s: %zu covered pixels, %u frames: mean %.4f (exact %.4f), worst pixel %.1f%%, %zu channels outside\n",
                unbiased ? "unbiased" : "biased", covered, kFrames, sum / double(covered), kExact, 100.0 * worst, outside);
    EXPECT_EQ(covered, size_t(kW) * kH);  // the camera sits inside the sphere
    EXPECT_EQ(outside, 0u);
    EXPECT_NEAR(sum / double(covered) / kExact, 1.0, 0.03);
    EXPECT_TRUE(finite_rgba(img.rgba));
  }
}

// ---- 3. Cornell box ---------------------------------------------------------------------------
// The image against the CPU path tracer with max_bounces 2 (emission + direct + one bounce),
// compared by means over the covered pixels that do not see the light (per channel summed). The
// path tracer's mean has its standard error from its per-pixel variances; the GPU's from the
// spread of the frames' means. The tolerances are in the test, with what they allow for.

struct ImageMean {
  double mean = 0.0, se = 0.0;
};

ImageMean gpu_mean(const surface::HtexGiImage& out, const std::vector<bool>& mask) {
  std::vector<double> per_frame;
  for (const auto& f : out.frames) {
    double s = 0.0;
    size_t n = 0;
    for (size_t p = 0; p < mask.size(); ++p)
      if (mask[p]) {
        s += double(f[4 * p]) + double(f[4 * p + 1]) + double(f[4 * p + 2]);
        ++n;
      }
    per_frame.push_back(s / double(std::max<size_t>(n, 1)));
  }
  ImageMean m;
  for (double v : per_frame) m.mean += v / double(per_frame.size());
  double sq = 0.0;
  for (double v : per_frame) sq += (v - m.mean) * (v - m.mean);
  m.se = std::sqrt(sq / double(per_frame.size() - 1) / double(per_frame.size()));
  return m;
}

TEST_F(HtexGiTest, CornellBoxMatchesThePathTracersOneBounce) {
  // 96x72 with 4 texels per unit: the level of detail then gives texels of about a pixel, as the
  // window and the bench use Htex (at coarse texels every pixel blends a few texels, many of
  // them at the box's concave corners, and the image away from the light reads 22-24% low:
  // docs/results.md). The mean is taken over the pixels that do not see the light: the light's
  // few pixels (radiance ~17 against ~0.1) would otherwise dominate it and hide the walls.
  constexpr uint32_t kW = 96, kH = 72, kFrames = 8;
  const SurfaceScene scene = make_cornell_box();
  reference::PathTracerSettings ps;
  ps.width = kW;
  ps.height = kH;
  ps.samples_per_pixel = 64;
  ps.max_bounces = 2;
  ps.roulette_after = 2;
  ps.seed = 5;
  const reference::PathTracedImage ref = reference::path_trace(scene, scene.camera, ps);

  GiRig g(device(), scene, 4.0, 256);
  ImageMean result[2];
  std::vector<bool> mask;
  for (const bool unbiased : {false, true}) {
    g.gi.reset();
    g.rig.pass->reset_residency();
    RestirGiSettings s;
    s.unbiased = unbiased;
    const auto out = g.render(device(), scene.camera, kW, kH, kFrames, s, 0, true);
    EXPECT_FALSE(out.image.counters.overflow);
    EXPECT_EQ(out.image.counters.hole_pixels, 0u);
    EXPECT_TRUE(finite_rgba(out.image.rgba));
    mask.assign(size_t(kW) * kH, false);
    for (size_t p = 0; p < mask.size(); ++p) {
      const glm::dvec3& r = ref.mean[p];
      mask[p] = out.image.rgba[4 * p + 3] == 1.0f && r.x + r.y + r.z < 3.0;  // covered, not the light
    }
    result[unbiased ? 1 : 0] = gpu_mean(out, mask);
  }
  ImageMean r;
  size_t n = 0;
  double var = 0.0;
  for (size_t p = 0; p < mask.size(); ++p)
    if (mask[p]) {
      r.mean += ref.mean[p].x + ref.mean[p].y + ref.mean[p].z;
      const glm::dvec3 v = ref.variance[p];
      var += (v.x + v.y + v.z) / ps.samples_per_pixel;  // channels summed: an upper bound ignoring their covariance sign
      ++n;
    }
  ASSERT_GT(n, mask.size() / 2);
  r.mean /= double(n);
  r.se = std::sqrt(var) / double(n) * std::sqrt(3.0);
  std::printf("cornell htex+gi away from the light, %zu pixels, %u frames: path tracer %.5f +- %.5f; biased %.5f +- %.5f (%+.2f%%); "
              "unbiased %.5f +- %.5f (%+.2f%%)\n",
              n, kFrames, r.mean, r.se, result[0].mean, result[0].se, 100.0 * (result[0].mean / r.mean - 1.0), result[1].mean,
              result[1].se, 100.0 * (result[1].mean / r.mean - 1.0));
  // What is allowed, from what was measured and why (docs/results.md): the direct light's
  // four-point emitter shadow ratio reads ~4% under the path tracer's exact soft shadows; biased
  // reuse loses ~8-10% of the one-bounce light (a quarter of the total here), about 2.5% of the
  // total; the unbiased combination keeps the indirect mean. So: biased within 8% + 4 sigma,
  // unbiased within 6% + 4 sigma, and unbiased no darker than biased beyond 4 sigma.
  const double sb = std::sqrt(result[0].se * result[0].se + r.se * r.se), su = std::sqrt(result[1].se * result[1].se + r.se * r.se);
  EXPECT_LT(std::abs(result[0].mean - r.mean), 0.08 * r.mean + 4.0 * sb);
  EXPECT_LT(std::abs(result[1].mean - r.mean), 0.06 * r.mean + 4.0 * su);
  const double sigma = std::sqrt(result[0].se * result[0].se + result[1].se * result[1].se);
  EXPECT_GT(result[1].mean, result[0].mean - 4.0 * sigma);
}

// ---- 4. Disocclusion and the fallback layer ---------------------------------------------------
// Six frames from one camera, then the camera moves closer: the pixels whose footprint reads a
// texel of a shadel not shaded (marked) in the previous frame have no history there (newly
// allocated, or finer levels of the same surfaces). After that one
// frame their error against the path tracer is lower with the fallback layer (whose reservoirs
// the first camera's texels wrote at a coarser level over the same surfaces) than without.

TEST_F(HtexGiTest, FallbackLayerLowersTheErrorWhereShadelsAreNew) {
  constexpr uint32_t kW = 32, kH = 24;
  const SurfaceScene scene = make_cornell_box();
  Camera near = scene.camera;
  near.eye = scene.camera.eye + 0.5 * (scene.camera.target - scene.camera.eye);  // closer: finer levels
  reference::PathTracerSettings ps;
  ps.width = kW;
  ps.height = kH;
  ps.samples_per_pixel = 256;
  ps.max_bounces = 2;
  ps.roulette_after = 2;
  ps.seed = 9;
  const reference::PathTracedImage ref = reference::path_trace(scene, near, ps);

  // Level-0 quads of 64 texels; a persistent layer of 4096 texels over the 6 meshes (8 x 8 per
  // quad here): coarser than what either camera reads, so the first camera's texels write every
  // persistent texel the second camera's new texels fall in.
  GiRig g(device(), scene, 0.1, 64, surface::HtexGiOptions{.persistent_texel_budget = 4096});
  double rms[2] = {0.0, 0.0};
  size_t fresh = 0;
  for (const bool fallback : {false, true}) {
    RestirGiSettings s;
    s.fallback = fallback;
    double sq = 0.0;
    size_t count = 0;
    for (uint32_t seed = 0; seed < 3; ++seed) {  // three runs with other random streams
      g.gi.reset();
      g.rig.pass->reset_residency();
      const uint32_t first = 100 * seed;
      g.render(device(), scene.camera, kW, kH, 6, s, first);
      const std::vector<uint32_t> before = g.rig.read<uint32_t>(g.rig.pass->occupancy());
      const auto out = g.render(device(), near, kW, kH, 1, s, first + 6);
      EXPECT_TRUE(finite_rgba(out.image.rgba));
      for (size_t p = 0; p < size_t(kW) * kH; ++p) {
        const glm::uvec4 vis = out.image.visibility[p];
        if (vis.x == 0 || out.image.rgba[4 * p + 3] != 1.0f) continue;
        const auto [mesh, tri] = g.rig.local_triangle(vis.x - 1);
        const auto face = uint32_t(g.rig.geometry.meshes[mesh].face_of_triangle[tri]);
        const auto fp = reference::htex_footprint(g.rig.geometry.meshes, g.rig.geometry.layout, mesh, face, stored_barycentrics(vis), vis.y);
        bool is_new = false;
        for (uint32_t k = 0; k < fp.count; ++k) {
          const glm::uvec2 v = g.rig.geometry.layout.virtual_texel(fp.texels[k].texel);
          const uint32_t group = g.rig.geometry.layout.group_of(v), bit = ((v.y / 8) % 8) * 8 + (v.x / 8) % 8;
          is_new |= (before[2 * group + bit / 32] & (1u << (bit % 32))) == 0;  // its shadel was not shaded last frame
        }
        if (!is_new) continue;
        for (int c = 0; c < 3; ++c) {
          const double d = double(out.image.rgba[4 * p + size_t(c)]) - ref.mean[p][c];
          sq += d * d;
        }
        ++count;
      }
    }
    fresh = count;
    rms[fallback ? 1 : 0] = std::sqrt(sq / double(std::max<size_t>(count, 1)));
  }
  std::printf("persistent layer: levels %u.., %llu texels\n", g.gi.persistent_levels()[0], static_cast<unsigned long long>(g.gi.persistent_texels()));
  std::printf("disocclusion: %zu newly allocated pixel samples over 3 runs: RMS error after one frame %.5f without the fallback "
              "layer, %.5f with it\n",
              fresh, rms[0], rms[1]);
  ASSERT_GT(fresh, size_t(kW) * kH / 4);
  EXPECT_LT(rms[1], rms[0]);
}

}  // namespace
}  // namespace prismoid::test
