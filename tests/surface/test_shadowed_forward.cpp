// The shadowed forward backend (depth pre-pass with triangle ids, then one ray-generation
// shading invocation per pixel with shadow rays; lavapipe, validation on) against the CPU
// double twin (reference::direct_light with shadows): every compared pixel within the tolerance
// forward_comparison.hpp derives, ambiguous shadow rays counted and bounded; umbrae where the
// geometry puts them; no self-shadowing far from the origin.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "scene/surface_generators.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/forward_comparison.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

double max_abs(const glm::dvec3& v) { return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z))); }

class ShadowedForwardTest : public GpuTest {
 protected:
  void SetUp() override {
    GpuTest::SetUp();
    if (!device().ray_tracing_enabled()) GTEST_SKIP() << "no ray tracing on " << device().capabilities().name;
  }
  ForwardComparison compare(const SurfaceScene& scene, uint32_t w = 96, uint32_t h = 72, glm::dvec2 subpixel = glm::dvec2(0.0)) {
    surface::ShadowedForwardPass pass(device());
    return compare_forward_shadowed(device(), pass, scene, scene.camera, w, h, subpixel);
  }
  void expect_agreement(const ForwardComparison& r, const std::string& what, double max_excluded_fraction = 0.05) {
    EXPECT_TRUE(r.finite) << what;
    EXPECT_EQ(r.failures, 0u) << what << ": " << r.failures << " pixels outside the tolerance, first: " << r.first_failure;
    EXPECT_GT(r.covered, r.pixels / 10) << what;
    EXPECT_LE(double(r.excluded), max_excluded_fraction * double(r.pixels)) << what;
    EXPECT_LT(double(r.ambiguous), 0.02 * double(r.pixels)) << what;
    size_t covered = 0;
    for (size_t i = 0; i < r.pixels; ++i) covered += r.gpu.rgba[i * 4 + 3] == 1.0f;
    EXPECT_EQ(r.gpu.shading_invocations, covered) << what << ": one shading invocation per covered pixel";
    std::printf("[ %s ] compared %zu of %zu pixels (%zu covered, %zu silhouette, %zu ambiguous = %.3f%%, %zu changed by shadows): "
                "max error %.3g, max error/tolerance %.3g\n",
                what.c_str(), r.compared, r.pixels, r.covered, r.excluded, r.ambiguous, 100.0 * double(r.ambiguous) / double(r.pixels),
                r.shadowed, r.max_error, r.max_ratio);
  }
};

// The Cornell box: the blocks shadow the ceiling light (4 weighted points per emitter triangle).
TEST_F(ShadowedForwardTest, CornellBoxMatchesShadowedTwin) {
  const ForwardComparison r = compare(make_cornell_box());
  expect_agreement(r, "Cornell box, shadows", 0.1);
  EXPECT_GT(r.shadowed, r.pixels / 20) << "the shadows change the image";
}

// The unshadowed sphere scene (nothing occludes any light from a visible point): the same image
// as the unshadowed twin, smooth and flat, GGX, sub-pixel offset: the hooks add nothing there.
TEST_F(ShadowedForwardTest, UnoccludedSphereMatchesTwinAndCastsNoShadow) {
  for (bool smooth : {true, false}) {
    SphereSceneOptions o;
    o.ggx = true;
    o.smooth = smooth;
    o.sky = true;
    const ForwardComparison r = compare(sphere_scene(o), 64, 48, {0.25, -0.375});
    expect_agreement(r, std::string("sphere, ") + (smooth ? "smooth" : "flat"));
    EXPECT_EQ(r.shadowed, 0u) << "a convex sphere does not shadow itself";
  }
}

// Where the floor point's segment to the light crosses the occluder's square (inside / outside
// it by 5% of its side): the umbra is exactly the sky's ambient term, outside the unshadowed
// direct light. Counts of both kinds must be substantial.
void check_umbra(const vk::Device& device, ShadowLight kind, const glm::dvec3& offset, const char* what) {
  const SurfaceScene scene = translated(occluder_scene(kind), offset);
  const uint32_t w = 96, h = 72;
  surface::ShadowedForwardPass pass(device);
  const surface::GpuSurfaceScene gpu = surface::upload(device, scene);
  const rt::SceneAccel accel(device, scene);
  const surface::ForwardImage image = surface::render_forward_shadowed(device, pass, gpu, accel, scene.camera, {w, h});
  const reference::DirectLightImage unshadowed = reference::direct_light_image(scene, scene.camera, w, h);
  const glm::dvec3 floor_albedo = scene.materials[0].albedo;
  const glm::dvec3 ambient = floor_albedo * reference::sky_cosine_mean(scene.sky, {0.0, 1.0, 0.0});
  size_t inside = 0, outside = 0, wrong = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const reference::DirectLightSample& s = unshadowed.pixels[i];
      if (!s.hit || s.mesh != 0) continue;
      bool edge = false;  // next to another mesh or the sky: the rasterizer may keep either side
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = int(x) + dx, ny = int(y) + dy;
          if (nx < 0 || ny < 0 || nx >= int(w) || ny >= int(h)) continue;
          const reference::DirectLightSample& n = unshadowed.pixels[size_t(ny) * w + size_t(nx)];
          edge = edge || !n.hit || n.mesh != 0;
        }
      if (edge) continue;
      const glm::dvec3 d = reference::ray_direction(scene.camera, w, h, x + 0.5, y + 0.5);
      const glm::dvec3 p = scene.camera.eye + s.t * d - offset;  // on the floor, scene at the origin
      glm::dvec3 cross;
      if (kind == ShadowLight::Point) cross = p + (kShadowPointLight - p) * (kOccluderY / kShadowPointLight.y);
      else cross = p - glm::normalize(kShadowDirection) * (kOccluderY / -glm::normalize(kShadowDirection).y);
      const double margin = std::min(0.5 * kOccluderSize - std::abs(cross.x - kOccluderX), 0.5 * kOccluderSize - std::abs(cross.z - kOccluderZ));
      const double u = 0x1p-24, rounding = u * (kUlpBudget + s.terms) * s.rounding_scale;
      const glm::dvec3 g(image.rgba[i * 4], image.rgba[i * 4 + 1], image.rgba[i * 4 + 2]);
      if (margin > 0.05 * kOccluderSize) {
        ++inside;
        if (max_abs(g - ambient) > rounding) ++wrong;
      } else if (margin < -0.05 * kOccluderSize) {
        ++outside;
        if (max_abs(g - s.radiance) > rounding) ++wrong;
      }
    }
  EXPECT_EQ(wrong, 0u) << what;
  EXPECT_GT(inside, 100u) << what;
  EXPECT_GT(outside, 1000u) << what;
  std::printf("[ %s ] %zu floor pixels deep in the umbra (= ambient), %zu deep outside (= unshadowed), %zu wrong\n", what, inside, outside,
              wrong);
}

TEST_F(ShadowedForwardTest, PointLightUmbraIsAmbientAndOutsideIsUnshadowed) {
  check_umbra(device(), ShadowLight::Point, glm::dvec3(0.0), "point light");
  expect_agreement(compare(occluder_scene(ShadowLight::Point)), "occluder, point light");
}

TEST_F(ShadowedForwardTest, DirectionalLightUmbraIsAmbientAndOutsideIsUnshadowed) {
  check_umbra(device(), ShadowLight::Directional, glm::dvec3(0.0), "directional light");
  expect_agreement(compare(occluder_scene(ShadowLight::Directional)), "occluder, directional light");
}

// 1e6 from the origin the scene renders as at the origin (positions relative to the bounds
// centre on both sides): the same umbra, the twin's image, and no acne: lit by a grazing
// directional light (5 degrees above the floor) and a point light, with nothing in the way,
// no floor pixel is darker than the unshadowed direct light.
TEST_F(ShadowedForwardTest, FarFromOriginHasTheSameShadowsAndNoAcne) {
  const glm::dvec3 offset(1e6, -1e6, 1e6);
  check_umbra(device(), ShadowLight::Point, offset, "point light, 1e6 away");
  check_umbra(device(), ShadowLight::Directional, offset, "directional light, 1e6 away");
  expect_agreement(compare(translated(occluder_scene(ShadowLight::Point), offset)), "occluder 1e6 away");

  for (const glm::dvec3& where : {glm::dvec3(0.0), offset}) {
    SurfaceScene open = occluder_scene(ShadowLight::Directional);
    open.meshes.pop_back();  // no occluder
    open.directional_lights = {{{-std::cos(0.0873), -std::sin(0.0873), 0.0}, {2.0, 2.0, 2.0}}};
    open.point_lights = {{{-1.5, 0.4, 1.0}, {1.0, 1.0, 1.0}}};
    open.meshes.push_back(horizontal_quad("far floor", 0.0, 0.0, 5.0, 6.0, 0));  // a second mesh, coplanar, adjacent
    open = translated(open, where);
    const uint32_t w = 96, h = 72;
    surface::ShadowedForwardPass pass(device());
    const surface::GpuSurfaceScene gpu = surface::upload(device(), open);
    const rt::SceneAccel accel(device(), open);
    const surface::ForwardImage image = surface::render_forward_shadowed(device(), pass, gpu, accel, open.camera, {w, h});
    const reference::DirectLightImage unshadowed = reference::direct_light_image(open, open.camera, w, h);
    size_t lit = 0, dark = 0;
    for (size_t i = 0; i < unshadowed.pixels.size(); ++i) {
      const reference::DirectLightSample& s = unshadowed.pixels[i];
      const size_t x = i % w, y = i / w;
      bool edge = false;  // next to the sky: the rasterizer may keep either
      for (size_t j : {i - 1, i + 1, i - w, i + w})
        edge = edge || x == 0 || y == 0 || x + 1 == w || y + 1 == h || !unshadowed.pixels[j].hit;
      if (!s.hit || edge) continue;
      ++lit;
      const double rounding = 0x1p-24 * (kUlpBudget + s.terms) * s.rounding_scale;
      const glm::dvec3 g(image.rgba[i * 4], image.rgba[i * 4 + 1], image.rgba[i * 4 + 2]);
      if (s.radiance.x - g.x > rounding || s.radiance.y - g.y > rounding || s.radiance.z - g.z > rounding) ++dark;
    }
    EXPECT_EQ(dark, 0u) << "self-shadowing acne at offset " << where.x;
    EXPECT_GT(lit, size_t(w) * h / 3);
    std::printf("[ acne, offset %g ] %zu lit floor pixels, %zu darker than unshadowed\n", where.x, lit, dark);
  }
}

}  // namespace
}  // namespace prismoid::test
