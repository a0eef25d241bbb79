// The CPU reference of the forward backend (renderer/reference/direct_light): closed forms, and
// agreement with the path tracer's single-bounce estimate where nothing occludes a light.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/path_tracer.hpp"
#include "scene/surface_generators.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::reference {
namespace {

constexpr double kPi = std::numbers::pi;

double max_of(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }

// From a point on a convex closed polyhedron's inside, the other faces cover the point's whole
// hemisphere: with every face emitting Le and reflecting albedo A diffusely, the direct light is
// Le + A Le, whatever the tessellation.
TEST(DirectLight, FurnaceFromInsideIsEmissionTimesOnePlusAlbedo) {
  const SurfaceScene furnace = make_furnace(0.5, 2.0, 2);
  const DirectLightImage image = direct_light_image(furnace, furnace.camera, 20, 16);
  for (const auto& p : image.pixels) {
    ASSERT_TRUE(p.hit);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(p.radiance[c], 3.0, 1e-11);
  }
}

// A point light straight above a diffuse square: albedo / pi * I / d^2 at the foot; from below
// (the back) the same (two-sided reflection); an emitter seen from behind is black.
TEST(DirectLight, PointLightAndOneSidedEmissionFollowTheConventions) {
  SurfaceScene s;
  s.materials = {{"white", glm::dvec3(0.6), glm::dvec3(0.0), 1.0, glm::dvec3(0.0)}};
  s.meshes.push_back(test::facing_quad({0, 0, 0}, {0, 0, 1}, 2.0, 0));
  s.point_lights.push_back({{0, 0, 2}, glm::dvec3(4.0)});
  const SurfaceRay down[] = {{{0.0, 0.0, 5.0}, {0.0, 0.0, -1.0}, 0.0}};
  const auto front = direct_light(s, down);
  ASSERT_TRUE(front[0].hit);
  EXPECT_NEAR(front[0].radiance.x, 0.6 / kPi * 4.0 / 4.0, 1e-14);
  s.point_lights[0].position.z = -2.0;
  const SurfaceRay up[] = {{{0.0, 0.0, -5.0}, {0.0, 0.0, 1.0}, 0.0}};
  EXPECT_NEAR(direct_light(s, up)[0].radiance.x, 0.6 / kPi, 1e-14);
  s.point_lights.clear();
  s.materials[0].emission = glm::dvec3(2.0);
  EXPECT_EQ(direct_light(s, down)[0].radiance, glm::dvec3(2.0));
  EXPECT_EQ(direct_light(s, up)[0].radiance, glm::dvec3(0.0));
}

// The path tracer with one reflection (emission + direct light, with shadows, the sky through
// BSDF sampling) converges to the same image on the convex sphere, where nothing occludes a
// light: the independent check that both follow the same units and conventions. Diffuse: with
// the sky (the forward sky term is exact for a flat-shaded convex object with nothing around).
// GGX: the exact area-light rule, no sky (forward leaves the sky's specular reflection out).
void expect_matches_path_tracer(const SurfaceScene& scene, AreaLightRule rule) {
  const uint32_t w = 16, h = 16;
  PathTracerSettings pt;
  pt.width = w;
  pt.height = h;
  pt.samples_per_pixel = 4096;
  pt.max_bounces = 1;
  pt.roulette_after = 1;  // no Russian roulette
  pt.jitter = false;      // through the pixel centres, as the direct-light image
  const PathTracedImage traced = path_trace(scene, scene.camera, pt);
  DirectLightOptions options;
  options.area_rule = rule;
  const DirectLightImage direct = direct_light_image(scene, scene.camera, w, h, 0.0, 0.0, options);
  double worst_sigma = 0.0;
  glm::dvec3 sum_direct(0.0), sum_traced(0.0), sum_var(0.0);
  for (size_t i = 0; i < direct.pixels.size(); ++i) {
    const glm::dvec3 se = traced.standard_error(i);
    for (int c = 0; c < 3; ++c) {
      const double diff = std::abs(direct.pixels[i].radiance[c] - traced.mean[i][c]);
      // 5 standard errors, and 1e-6 for the pixels where the estimate has no variance.
      EXPECT_LE(diff, 5.0 * se[c] + 1e-6) << "pixel " << i << " channel " << c;
      if (se[c] > 0.0) worst_sigma = std::max(worst_sigma, diff / se[c]);
    }
    sum_direct += direct.pixels[i].radiance;
    sum_traced += traced.mean[i];
    sum_var += se * se;
  }
  for (int c = 0; c < 3; ++c) EXPECT_LE(std::abs(sum_direct[c] - sum_traced[c]), 4.0 * std::sqrt(sum_var[c]));
  std::printf("[ path tracer ] worst pixel difference: %.2f standard errors\n", worst_sigma);
}

TEST(DirectLight, DiffuseSphereMatchesPathTracerSingleBounce) {
  test::SphereSceneOptions o;
  o.smooth = false;
  o.sky = true;
  expect_matches_path_tracer(test::sphere_scene(o), AreaLightRule::Forward);
}

TEST(DirectLight, GgxSphereMatchesPathTracerSingleBounce) {
  test::SphereSceneOptions o;
  o.smooth = true;
  o.ggx = true;
  expect_matches_path_tracer(test::sphere_scene(o), AreaLightRule::Exact);
}

// The forward rule's quadrature error for the GGX lobe under the quad light, against the exact
// integral, pixel by pixel: the rule is second order and the light is small (0.5 wide, 1.2 to
// 2.2 from the sphere's visible points: 13 to 23 degrees across), so with n = 4 the error stays
// within 1% of the peak radiance at roughness 0.5.
TEST(DirectLight, ForwardAreaRuleIsCloseToTheExactIntegral) {
  test::SphereSceneOptions o;
  o.ggx = true;
  o.lights = test::Lights::Area;
  const SurfaceScene scene = test::sphere_scene(o);
  DirectLightOptions exact;
  exact.area_rule = AreaLightRule::Exact;
  const auto a = direct_light_image(scene, scene.camera, 48, 48);
  const auto b = direct_light_image(scene, scene.camera, 48, 48, 0.0, 0.0, exact);
  double worst = 0.0, largest = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    worst = std::max(worst, max_of(glm::abs(a.pixels[i].radiance - b.pixels[i].radiance)));
    largest = std::max(largest, max_of(b.pixels[i].radiance));
  }
  EXPECT_GT(largest, 0.1);
  EXPECT_LT(worst, 1e-2 * largest);
  std::printf("[ forward rule ] max |forward - exact| = %.3g of the peak radiance %.3g\n", worst / largest, largest);
}

// The "never black" rule: a surface file's scene has no light; with_default_lighting adds a
// headlight and a sky whose cosine-weighted mean is at least (top + bottom) / 2 - (top - bottom) / 3,
// so every visible point of the default material (albedo 0.8) has at least 0.8 times that.
TEST(DirectLight, DefaultLightingLeavesNoVisibleSurfaceBlack) {
  SurfaceMesh sphere = make_icosphere(glm::dvec3(3.0, -1.0, 2.0), 2.0, 2);
  sphere.name = "sphere.off";
  const SurfaceScene bare = make_surface_scene(sphere);
  ASSERT_FALSE(has_light(bare));
  const SurfaceScene lit = with_default_lighting(bare, bare.camera);
  const DirectLightImage image = direct_light_image(lit, lit.camera, 32, 32);
  const double floor = 0.8 * (0.5 * (kDefaultSkyTop + kDefaultSkyBottom) - (kDefaultSkyTop - kDefaultSkyBottom) / 3.0);
  size_t hits = 0;
  for (const auto& p : image.pixels)
    if (p.hit) {
      ++hits;
      for (int c = 0; c < 3; ++c) EXPECT_GE(p.radiance[c], floor * (1.0 - 1e-12));
    }
  EXPECT_GT(hits, 200u);
}

}  // namespace
}  // namespace prismoid::reference
