// The texel shading backend's passes on the GPU (lavapipe, validation on) against the
// double-precision CPU side (renderer/surface/texel/texel_atlas.hpp, reference::direct_light_at):
// the queued tiles are exactly the tiles of the visible pixels' bilinear taps, every shaded
// texel is the direct-light reference at its texel point, every gathered pixel is the bilinear
// lookup of the shaded texels, no pixel reads an unshaded texel, shading is reused across
// frames up to the age threshold, the mip bias lowers the shading rate, and where shading is
// constant on each face the image is the forward backend's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <set>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/texel/texel_pass.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/forward_comparison.hpp"
#include "surface/htex_fixture.hpp"
#include "surface/surface_test_scenes.hpp"
#include "surface/texture_space_checks.hpp"

namespace prismoid::test {
namespace {

constexpr uint32_t kW = 96, kH = 72;

texel::AtlasSettings density(double texels_per_unit, uint32_t levels = 4) {
  texel::AtlasSettings a;
  a.texels_per_unit = texels_per_unit;
  a.levels = levels;
  return a;
}

surface::TexelSettings unshadowed() {
  surface::TexelSettings s;
  s.shadows = false;
  return s;
}

struct TexelRig {
  TexelRig(const vk::Device& device, SurfaceScene s, const texel::AtlasSettings& a, const surface::TexelSettings& settings)
      : scene(std::move(s)),
        gpu(surface::upload(device, scene)),
        accel(device, scene),
        atlas(texel::build_texel_atlas(scene, a)),
        pass(std::make_unique<surface::TexelPass>(device, atlas, settings)),
        triangles(scene) {}
  surface::TexelImage render(const vk::Device& device, const Camera& camera, uint32_t w = kW, uint32_t h = kH) {
    return surface::render_texel(device, *pass, gpu, accel.tlas(), camera, {w, h});
  }
  template <typename T>
  std::vector<T> read(const vk::Buffer& buffer) const {
    return read_as<T>(*pass, buffer);
  }
  std::pair<uint32_t, uint32_t> local_triangle(uint32_t global) const { return triangles.local(global); }
  uint32_t tile_of(uint32_t level, glm::uvec2 t) const {
    return uint32_t(atlas.tile_offset(level)) + (t.y / 8) * (atlas.level_width(level) / 8) + t.x / 8;
  }
  size_t texel_of(uint32_t level, glm::uvec2 t) const { return size_t(atlas.texel_offset(level)) + size_t(t.y) * atlas.level_width(level) + t.x; }

  SurfaceScene scene;
  surface::GpuSurfaceScene gpu;
  rt::SceneAccel accel;
  texel::TexelAtlas atlas;
  std::unique_ptr<surface::TexelPass> pass;
  TriangleIndex triangles;
};

struct PixelPoint {
  size_t pixel = 0;
  uint32_t triangle = 0, level = 0;
  glm::dvec3 bary{0.0};
};
std::vector<PixelPoint> pixel_points(const surface::TexelImage& img) {
  std::vector<PixelPoint> out;
  for (size_t i = 0; i < img.visibility.size(); ++i) {
    const glm::uvec4 v = img.visibility[i];
    if (v.x == 0) continue;
    out.push_back({i, v.x - 1, v.y, stored_barycentrics(v)});
  }
  return out;
}

// The taps' tiles of one pixel, as the CPU computes them in double: `required` for taps of
// weight > 1e-5 whose position is not within 1e-4 texel of a texel boundary (the float uv of
// the GPU is within ~1e-5 texel of the double one), `allowed` for every tap of the position
// moved by +-1e-4 texel.
void tap_tiles(const TexelRig& rig, const PixelPoint& p, std::set<uint32_t>& required, std::set<uint32_t>& allowed) {
  const glm::dvec2 uv = texel::atlas_uv(rig.atlas, p.triangle, p.bary);
  const double scale = double(1u << p.level);
  bool near_boundary = false;
  for (int a = 0; a < 2; ++a) {
    const double f = uv[a] / scale - 0.5;
    near_boundary = near_boundary || std::abs(f - std::round(f)) < 1e-4;
  }
  for (double dx : {-1e-4, 0.0, 1e-4})
    for (double dy : {-1e-4, 0.0, 1e-4}) {
      const auto taps = texel::bilinear_taps(rig.atlas, uv + glm::dvec2(dx, dy) * scale, p.level);
      for (const texel::Tap& t : taps) {
        if (rig.atlas.triangle_at(p.level, t.texel.x, t.texel.y) == texel::kNoTriangle) continue;
        allowed.insert(rig.tile_of(p.level, t.texel));
        if (dx == 0.0 && dy == 0.0 && !near_boundary && t.weight > 1e-5) required.insert(rig.tile_of(p.level, t.texel));
      }
    }
}

class TexelPassTest : public GpuTest {};

TEST_F(TexelPassTest, QueuesExactlyTheTilesOfTheVisiblePixelsTaps) {
  TexelRig rig(device(), sphere_scene({}), density(60.0), unshadowed());
  const surface::TexelImage img = rig.render(device(), rig.scene.camera);
  const auto tasks = rig.read<uint32_t>(rig.pass->tasks());
  const std::set<uint32_t> queued(tasks.begin(), tasks.begin() + img.counters.queued_tiles);
  EXPECT_EQ(queued.size(), img.counters.queued_tiles) << "a tile was queued twice";
  std::set<uint32_t> required, allowed;
  std::map<uint32_t, size_t> levels;
  const auto points = pixel_points(img);
  for (const PixelPoint& p : points) {
    ASSERT_LT(p.level, rig.atlas.levels);
    ++levels[p.level];
    tap_tiles(rig, p, required, allowed);
  }
  size_t missing = 0, extra = 0;
  for (uint32_t t : required) missing += !queued.count(t);
  for (uint32_t t : queued) extra += !allowed.count(t);
  EXPECT_EQ(missing, 0u);
  EXPECT_EQ(extra, 0u);
  EXPECT_EQ(img.counters.hole_pixels, 0u);
  EXPECT_GT(points.size(), size_t(kW * kH / 5));
  std::printf("%zu pixels, %u tiles queued (%zu required), %u texels shaded; levels:", points.size(), img.counters.queued_tiles,
              required.size(), img.counters.shaded_texels);
  for (const auto& [l, n] : levels) std::printf(" %u: %zu", l, n);
  std::printf("\n");
}

TEST_F(TexelPassTest, ShadesEveryQueuedTexelAndGathersTheBilinearLookup) {
  for (const bool ggx : {false, true}) {
    SphereSceneOptions o;
    o.ggx = ggx;
    o.sky = true;
    TexelRig rig(device(), sphere_scene(o), density(60.0), unshadowed());
    const Camera camera = rig.scene.camera;
    const surface::TexelImage img = rig.render(device(), camera);
    const auto tasks = rig.read<uint32_t>(rig.pass->tasks());
    const auto result = rig.read<glm::vec4>(rig.pass->result());
    ASSERT_GT(img.counters.queued_tiles, 0u);

    // Every texel of every queued tile that holds a triangle, and its CPU twin.
    std::vector<reference::ShadingPointQuery> queries;
    std::vector<size_t> slots;
    for (uint32_t k = 0; k < img.counters.queued_tiles; ++k) {
      uint32_t level = 0;
      while (level + 1 < rig.atlas.levels && tasks[k] >= rig.atlas.tile_offset(level + 1)) ++level;
      const uint32_t local = tasks[k] - uint32_t(rig.atlas.tile_offset(level)), tiles_x = rig.atlas.level_width(level) / 8;
      for (uint32_t q = 0; q < 64; ++q) {
        const glm::uvec2 t((local % tiles_x) * 8 + q % 8, (local / tiles_x) * 8 + q / 8);
        const uint32_t tri = rig.atlas.triangle_at(level, t.x, t.y);
        if (tri == texel::kNoTriangle) continue;
        const auto [mesh, local_tri] = rig.local_triangle(tri);
        queries.push_back({mesh, local_tri, texel::texel_barycentric(rig.atlas, tri, level, t.x, t.y), camera.eye});
        slots.push_back(rig.texel_of(level, t));
      }
    }
    EXPECT_EQ(queries.size(), img.counters.shaded_texels);
    std::vector<glm::vec4> gpu_values;
    for (size_t k : slots) gpu_values.push_back(result[k]);
    const SampleCheck shading = check_shaded_samples(rig.scene, queries, gpu_values);
    EXPECT_EQ(shading.failures, 0u);
    EXPECT_GT(shading.peak, 0.1);

    // Gather: the bilinear blend of the GPU's texels at the CPU's taps (bilinear_pixel_error).
    size_t gather_failures = 0;
    double worst_gather = 0.0;
    const auto points = pixel_points(img);
    for (const PixelPoint& p : points) {
      std::vector<std::pair<glm::vec4, double>> taps;
      for (const texel::Tap& t : texel::bilinear_taps(rig.atlas, texel::atlas_uv(rig.atlas, p.triangle, p.bary), p.level)) {
        if (rig.atlas.triangle_at(p.level, t.texel.x, t.texel.y) == texel::kNoTriangle) continue;
        taps.emplace_back(result[rig.texel_of(p.level, t.texel)], t.weight);
        ASSERT_EQ(taps.back().first.w, 1.0f) << "pixel " << p.pixel << " reads a texel never shaded";
      }
      const double e = bilinear_pixel_error(&img.rgba[4 * p.pixel], taps);
      worst_gather = std::max(worst_gather, e);
      if (e > 1.0 && gather_failures++ < 5) ADD_FAILURE() << "pixel " << p.pixel << ": " << e << " of the tolerance";
    }
    EXPECT_EQ(gather_failures, 0u);
    EXPECT_EQ(img.counters.hole_pixels, 0u);
    std::printf("[ shading %s ] %zu texels of %u tiles: worst error %.3g of tolerance (peak %.3g); gather: %zu pixels, worst %.3g of "
                "tolerance; atlas %u x %u, %zu charts, %llu bytes\n",
                ggx ? "GGX" : "diffuse", queries.size(), img.counters.queued_tiles, shading.worst, shading.peak, points.size(), worst_gather, rig.atlas.width,
                rig.atlas.height, rig.atlas.charts.size(), static_cast<unsigned long long>(img.counters.atlas_bytes));
  }
}

// The flat-shaded cube (texture_space_checks.hpp) equals the forward image.
TEST_F(TexelPassTest, FlatShadedCubeEqualsTheForwardImage) {
  TexelRig rig(device(), flat_cube_scene(), density(20.0), unshadowed());
  const surface::TexelImage img = rig.render(device(), rig.scene.camera);
  const size_t compared = expect_equals_forward(device(), rig.gpu, rig.scene.camera, kW, kH, img.rgba, img.visibility);
  EXPECT_GT(compared, size_t(kW * kH / 5));
  std::printf("%zu pixels equal to the forward image; %zu charts\n", compared, rig.atlas.charts.size());
}

// With an age threshold of 4 frames, a still camera queues nothing on frames 2-4 and draws the
// same image; frame 5 shades again; invalidate_shading() forces it.
TEST_F(TexelPassTest, ReusesShadingUpToTheAgeThreshold) {
  surface::TexelSettings s = unshadowed();
  s.max_age = 4;
  TexelRig rig(device(), sphere_scene({}), density(60.0), s);
  const Camera camera = rig.scene.camera;
  const surface::TexelImage first = rig.render(device(), camera);
  ASSERT_GT(first.counters.queued_tiles, 0u);
  for (int frame = 2; frame <= 4; ++frame) {
    const surface::TexelImage again = rig.render(device(), camera);
    EXPECT_EQ(again.counters.queued_tiles, 0u) << "frame " << frame;
    EXPECT_EQ(again.rgba, first.rgba) << "frame " << frame;
  }
  EXPECT_EQ(rig.render(device(), camera).counters.queued_tiles, first.counters.queued_tiles);  // frame 5: older than 4 frames
  rig.render(device(), camera);
  rig.pass->invalidate_shading();
  EXPECT_EQ(rig.render(device(), camera).counters.queued_tiles, first.counters.queued_tiles);
}

// The mip bias: +1 moves every pixel one level coarser (up to the coarsest) and shades fewer
// texels; the image stays free of holes.
TEST_F(TexelPassTest, MipBiasLowersTheShadingRate) {
  TexelRig rig(device(), sphere_scene({}), density(120.0), unshadowed());
  const surface::TexelImage base = rig.render(device(), rig.scene.camera);
  surface::TexelSettings s = unshadowed();
  s.lod_bias = 1.0f;
  rig.pass->set_settings(s);
  rig.pass->invalidate_shading();
  const surface::TexelImage biased = rig.render(device(), rig.scene.camera);
  size_t shifted = 0, covered = 0;
  for (size_t i = 0; i < base.visibility.size(); ++i) {
    if (base.visibility[i].x == 0) continue;
    ++covered;
    const uint32_t expect = std::min(base.visibility[i].y + 1, rig.atlas.levels - 1);
    shifted += biased.visibility[i].y == expect;
  }
  // Only pixels whose log2 footprint lies within float rounding of an integer may differ.
  EXPECT_GE(double(shifted), 0.99 * double(covered));
  EXPECT_LT(double(biased.counters.shaded_texels), 0.5 * double(base.counters.shaded_texels));
  EXPECT_EQ(biased.counters.hole_pixels, 0u);
  std::printf("bias 0: %u texels shaded; bias 1: %u (%.2fx fewer); %zu of %zu pixels one level coarser\n", base.counters.shaded_texels,
              biased.counters.shaded_texels, double(base.counters.shaded_texels) / double(std::max(1u, biased.counters.shaded_texels)), shifted,
              covered);
}

}  // namespace
}  // namespace prismoid::test
