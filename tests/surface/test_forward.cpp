// The forward surface backend on the GPU (lavapipe, validation on) against the CPU direct-light
// reference: every compared pixel within the tolerance forward_comparison.hpp derives, no NaN
// or infinity anywhere, one shading invocation per covered pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/forward_comparison.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

class ForwardTest : public GpuTest {
 protected:
  ForwardComparison compare(const SurfaceScene& scene, uint32_t w = 64, uint32_t h = 64, glm::dvec2 subpixel = glm::dvec2(0.0)) {
    surface::ForwardPass pass(device());
    return compare_forward(device(), pass, scene, scene.camera, w, h, subpixel);
  }
  // The comparison passed and was not vacuous: the silhouette band is a small part of the image.
  void expect_agreement(const ForwardComparison& r, const std::string& what, double max_excluded_fraction = 0.05) {
    EXPECT_TRUE(r.finite) << what;
    EXPECT_EQ(r.failures, 0u) << what << ": " << r.failures << " pixels outside the tolerance, first: " << r.first_failure;
    EXPECT_GT(r.covered, r.pixels / 10) << what;
    EXPECT_LE(double(r.excluded), max_excluded_fraction * double(r.pixels)) << what;
    std::printf("[ %s ] compared %zu of %zu pixels (%zu covered, %zu in the silhouette band): max error %.3g, max error/tolerance "
                "%.3g, rounding tolerance <= %.3g of the peak radiance\n",
                what.c_str(), r.compared, r.pixels, r.covered, r.excluded, r.max_error, r.max_ratio,
                r.max_rounding_tolerance / r.peak_radiance);
  }
};

TEST_F(ForwardTest, DiffuseSphereUnderEachLightMatchesReference) {
  for (Lights lights : {Lights::Point, Lights::Directional, Lights::Area}) {
    SphereSceneOptions o;
    o.lights = lights;
    expect_agreement(compare(sphere_scene(o)), "diffuse, light " + std::to_string(int(lights)));
  }
}

TEST_F(ForwardTest, GgxSphereUnderEachLightMatchesReference) {
  for (bool smooth : {true, false})
    for (Lights lights : {Lights::Point, Lights::Directional, Lights::Area}) {
      SphereSceneOptions o;
      o.ggx = true;
      o.smooth = smooth;
      o.lights = lights;
      expect_agreement(compare(sphere_scene(o)), std::string("GGX ") + (smooth ? "smooth" : "flat") + ", light " + std::to_string(int(lights)));
    }
}

// Colours per vertex (interpolated) and per triangle, under all lights and the sky; the sky
// is also what the pixels around the sphere must show.
TEST_F(ForwardTest, ColoursAndSkyMatchReference) {
  for (ColorBinding binding : {ColorBinding::PerVertex, ColorBinding::PerTriangle}) {
    SphereSceneOptions o;
    o.sky = true;
    o.ggx = binding == ColorBinding::PerTriangle;
    o.smooth = binding == ColorBinding::PerVertex;
    SurfaceScene scene = sphere_scene(o);
    SceneMesh& sphere = scene.meshes[0];
    sphere.color_binding = binding;
    const size_t n = binding == ColorBinding::PerVertex ? sphere.positions.size() : sphere.triangles.size();
    for (size_t i = 0; i < n; ++i)
      sphere.colors.push_back(glm::dvec3(double(i * 37 % 101) / 100.0, double(i * 53 % 97) / 96.0, double(i * 11 % 13) / 12.0));
    expect_agreement(compare(scene), binding == ColorBinding::PerVertex ? "per-vertex colours" : "per-triangle colours");
  }
}

// Seen from its centre, the furnace's direct light is Le (1 + A) at every pixel, exactly: all
// 1279 other triangles are area lights filling each point's hemisphere.
TEST_F(ForwardTest, FurnaceFromInsideIsEmissionTimesOnePlusAlbedo) {
  const SurfaceScene furnace = make_furnace(0.5, 2.0, 3);
  const ForwardComparison r = compare(furnace, 32, 32);
  expect_agreement(r, "furnace");
  for (size_t i = 0; i < r.pixels; ++i)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.gpu.rgba[i * 4 + c], 3.0, 3.0 * 1e-4) << "pixel " << i;
}

// At the largest emission the scene may hold (float32's largest value over 2^32), the furnace's
// Le (1 + A) still matches the reference; beyond it the upload refuses the scene, naming the
// material and the limit (float would upload Le = 1e300 as inf).
TEST_F(ForwardTest, FurnaceAtTheLargestEmissionFloatHoldsMatchesAndBeyondIsRefused) {
  const ForwardComparison r = compare(make_furnace(0.5, kMaxRadiometricValue, 3), 32, 32);
  expect_agreement(r, "furnace at the largest emission");
  for (size_t i = 0; i < r.pixels; ++i) EXPECT_NEAR(r.gpu.rgba[i * 4], 1.5 * kMaxRadiometricValue, 1.5e-4 * kMaxRadiometricValue);
  EXPECT_THROW(surface::upload(device(), make_furnace(0.5, 1e300, 1)), InputError);
  EXPECT_THROW(surface::upload(device(), make_furnace(0.5, 2.0 * kMaxRadiometricValue, 1)), InputError);
}

// Next to a corner of the emitters the area-light sum is ill-conditioned in float: a corner a
// few 1e-5 from the shading point has a short vector whose rounding turns its edges' planes by
// ~1e-3 rad. Before area_light.glsl took each edge's cross product from the shorter corner, the
// two emitters sharing such an edge got terms that no longer cancelled, and the sum came out up
// to 1e-3 above the closed form (0.1% on the H200, in ReSTIR GI's furnace). Now they cancel and
// the sum is the projected solid angle of a region inside the clipped hemisphere. Above the closed
// form, only the rounding of the terms is left: at most 19 emitters x 4 edges, each within 8 ulps
// of at most pi (the float atan's 4 and as many for the rest), halved by Lambert's formula and
// divided by pi: 76 * 8 * 2^-24 / 2 = 1.8e-5 of the area part A Le. Below it, the rounding of the
// point and of a corner vector (2^-24 each, coordinates below 1) tilts an edge that runs at
// distance d along the horizon by up to alpha = 2 * 2^-24 / d, which loses a sliver of at most
// alpha^2 (measured: up to 0.2 of that).
//
// A narrow camera at the centre of the icosahedron furnace looks straight at a corner: its
// pixels lie 0 to 3e-5 from the corner and its five edges; d is taken as the hit point's distance
// to the nearest plane of another emitter. Within a few PRISMOID_EMITTER_PLANE_EPSILON of one,
// that emitter is left out as coplanar (by the reference too), which removes its light there:
// those pixels are held to the bound from above only.
TEST_F(ForwardTest, FurnaceNextToACornerStaysAtTheClosedForm) {
  constexpr double kA = 0.5, kLe = 1.0, kArea = 1.8e-5;
  constexpr uint32_t kSize = 33;
  SurfaceScene furnace = make_furnace(kA, kLe, 0);
  Camera& camera = furnace.camera;
  camera.target = furnace.meshes[0].positions[0];
  camera.up = glm::normalize(glm::cross(camera.target, glm::dvec3(0.3, 0.1, 0.9)));
  camera.fovy_degrees = 0.003;
  const surface::GpuSurfaceScene gpu_scene = surface::upload(device(), furnace);
  // The same shading in a fragment shader (forward) and in a ray-generation shader (shadowed
  // forward, where emitter visibility may only remove light: held from above only). On the H200
  // the latter was up to 6.7e-3 above, from visibility ratios above 1 (shadow_rays.glsl), and
  // then up to 3e-4 above, from emitter terms summed between shadow rays, after which the
  // compiler's point was an ulp or so away from the first emitters' (shading.glsl,
  // surface_lights).
  std::vector<std::pair<std::string, surface::ForwardImage>> images;
  surface::ForwardPass pass(device());
  images.emplace_back("forward", surface::render_forward(device(), pass, gpu_scene, camera, {kSize, kSize}, {}));
  if (device().ray_tracing_enabled()) {
    surface::ShadowedForwardPass shadowed(device());
    const rt::SceneAccel accel(device(), furnace);
    images.emplace_back("shadowed", surface::render_forward_shadowed(device(), shadowed, gpu_scene, accel, camera, {kSize, kSize}));
  }
  const SceneMesh& m = furnace.meshes[0];
  for (const auto& [name, gpu] : images) {
    size_t clear = 0, near_plane = 0;
    double highest = 0.0, worst_clear = 0.0;
    for (uint32_t y = 0; y < kSize; ++y)
      for (uint32_t x = 0; x < kSize; ++x) {
        const size_t i = size_t(y) * kSize + x;
        const double v = gpu.rgba[i * 4 + 1];
        ASSERT_EQ(gpu.rgba[i * 4], v);  // grey
        const double area = (v - kLe) / (kA * kLe) - 1.0;  // relative error of the area part
        EXPECT_LT(area, kArea) << name << " pixel (" << x << ", " << y << ")";
        highest = std::max(highest, area);
        if (name != "forward") continue;
        // The double hit point's distance to the nearest plane of another emitter.
        const glm::dvec3 d = reference::ray_direction(camera, kSize, kSize, x + 0.5, y + 0.5);
        double hit_t = 1e30, plane = 1e30;
        size_t own = 0;
        for (size_t t = 0; t < m.triangles.size(); ++t) {
          const glm::dvec3 a = m.positions[m.triangles[t][0]];
          const glm::dvec3 n = glm::normalize(glm::cross(m.positions[m.triangles[t][1]] - a, m.positions[m.triangles[t][2]] - a));
          const double along = glm::dot(n, a) / glm::dot(n, d);  // closed and convex: the smallest positive is the hit
          if (along > 0.0 && along < hit_t) hit_t = along, own = t;
        }
        for (size_t t = 0; t < m.triangles.size(); ++t) {
          if (t == own) continue;
          const glm::dvec3 a = m.positions[m.triangles[t][0]];
          const glm::dvec3 n = glm::normalize(glm::cross(m.positions[m.triangles[t][1]] - a, m.positions[m.triangles[t][2]] - a));
          plane = std::min(plane, std::abs(glm::dot(n, hit_t * d - a)));
        }
        if (plane < 4.0 * PRISMOID_EMITTER_PLANE_EPSILON) {
          ++near_plane;
          continue;
        }
        ++clear;
        const double tilt = 2.0 * 0x1p-24 / plane;
        EXPECT_GT(area, -(kArea + tilt * tilt)) << "pixel (" << x << ", " << y << "), " << plane << " from another emitter's plane";
        worst_clear = std::max(worst_clear, -area / (kArea + tilt * tilt));
      }
    std::printf("furnace next to a corner, %s: highest pixel %+.1e of the area part", name.c_str(), highest);
    if (name == "forward") {
      std::printf("; %zu pixels clear of the other emitters' planes (lowest at %.2f of its bound), %zu within 4 plane epsilons of one",
                  clear, worst_clear, near_plane);
      EXPECT_GT(clear, size_t(kSize) * kSize / 2);
    }
    std::printf("\n");
  }
}

// A pass outlives the scenes it draws: the viewer keeps its passes when a dataset is replaced,
// and the next scene's buffers can land where the last one's were (the same address, handles
// Vulkan hands out again). Each pass must still draw the scene it is given: what it draws equals
// what a new pass draws, with no validation message (the descriptors of a destroyed scene).
TEST_F(ForwardTest, APassDrawsTheSceneMadeWhereTheLastOneWas) {
  SphereSceneOptions o;
  o.lights = Lights::Area;
  const SurfaceScene first = sphere_scene(o), second = make_cornell_box();
  const VkExtent2D extent{24, 20};
  surface::ForwardPass kept(device());
  std::optional<surface::GpuSurfaceScene> slot;
  slot.emplace(surface::upload(device(), first));
  const surface::ForwardImage before = surface::render_forward(device(), kept, *slot, first.camera, extent, {});
  slot.reset();
  slot.emplace(surface::upload(device(), second));
  const surface::ForwardImage after = surface::render_forward(device(), kept, *slot, second.camera, extent, {});
  surface::ForwardPass fresh(device());
  EXPECT_EQ(after.rgba, surface::render_forward(device(), fresh, *slot, second.camera, extent, {}).rgba);
  EXPECT_NE(after.rgba, before.rgba);
  if (device().ray_tracing_enabled()) {
    surface::ShadowedForwardPass kept_shadowed(device());
    std::optional<rt::SceneAccel> accel;
    slot.reset();
    slot.emplace(surface::upload(device(), first));
    accel.emplace(device(), first);
    surface::render_forward_shadowed(device(), kept_shadowed, *slot, *accel, first.camera, extent);
    accel.reset();
    slot.reset();
    slot.emplace(surface::upload(device(), second));
    accel.emplace(device(), second);
    const auto shadowed = surface::render_forward_shadowed(device(), kept_shadowed, *slot, *accel, second.camera, extent);
    surface::ShadowedForwardPass fresh_shadowed(device());
    EXPECT_EQ(shadowed.rgba, surface::render_forward_shadowed(device(), fresh_shadowed, *slot, *accel, second.camera, extent).rgba);
  }
}

// Shadows are not part of forward yet: the Cornell box against the unshadowed reference.
TEST_F(ForwardTest, CornellBoxMatchesUnshadowedReference) {
  expect_agreement(compare(make_cornell_box(), 64, 64), "Cornell box", 0.1);
}

TEST_F(ForwardTest, SubpixelOffsetSamplesTheOffsetPoint) {
  SphereSceneOptions o;
  o.ggx = true;
  o.sky = true;
  expect_agreement(compare(sphere_scene(o), 48, 40, {0.25, -0.375}), "sub-pixel offset (0.25, -0.375)");
}

// Positions are uploaded relative to the scene's centre: a copy 1e6 away renders as well.
TEST_F(ForwardTest, FarFromOriginCopyMatchesReference) {
  SphereSceneOptions o;
  o.ggx = true;
  const ForwardComparison near = compare(sphere_scene(o));
  const ForwardComparison far = compare(translated(sphere_scene(o), glm::dvec3(1e6, -1e6, 1e6)));
  expect_agreement(far, "1e6 from the origin");
  EXPECT_EQ(near.covered, far.covered);
}

// Zero-area triangles (repeated corner, collinear, one emissive) and a mesh whose normals are
// all zero: the image stays finite everywhere and matches the reference. Then a point light
// exactly at a vertex of the sphere (distance zero there, and in the plane of every triangle
// around that vertex, where float and double legitimately disagree about the horizon): finite.
TEST_F(ForwardTest, DegenerateTrianglesAndNormalsGiveFiniteImage) {
  SphereSceneOptions o;
  o.ggx = true;
  SurfaceScene scene = sphere_scene(o);
  scene.materials.push_back({"glow", glm::dvec3(0.5), glm::dvec3(0.04), 0.3, glm::dvec3(3.0)});
  SceneMesh junk;
  junk.name = "degenerate";
  junk.material = 2;
  junk.positions = {{0.2, 0.1, 1.5}, {0.4, 0.3, 1.5}, {0.6, 0.5, 1.5}, {0.2, 0.1, 1.5}};
  junk.triangles = {{0, 1, 2}, {0, 3, 1}, {1, 1, 1}};
  scene.meshes.push_back(junk);
  SceneMesh zero_normals = sphere_mesh({1.3, -0.8, 0.5}, 0.3, 1, true, 0);
  for (auto& n : zero_normals.normals) n = glm::dvec3(0.0);
  scene.meshes.push_back(zero_normals);
  const ForwardComparison r = compare(scene);
  expect_agreement(r, "degenerate input");

  scene.point_lights.push_back({scene.meshes[0].positions[5], glm::dvec3(0.5)});
  surface::ForwardPass pass(device());
  const surface::GpuSurfaceScene gpu = surface::upload(device(), scene);
  const surface::ForwardImage image = surface::render_forward(device(), pass, gpu, scene.camera, {64, 64});
  for (float v : image.rgba) ASSERT_TRUE(std::isfinite(v));
}

// The depth pre-pass is there so that shading runs once per covered pixel: counted per pixel
// (an atomic counter image) and in total (pipeline statistics, where the device has them), on
// a scene with three spheres behind each other, where drawing without the pre-pass would shade
// most pixels more than once.
TEST_F(ForwardTest, DepthPrePassShadesEachCoveredPixelOnce) {
  if (!device().capabilities().fragment_stores) GTEST_SKIP() << "no fragmentStoresAndAtomics";
  SurfaceScene scene = sphere_scene();
  scene.meshes.push_back(sphere_mesh({0.3, 0.2, -1.5}, 1.2, 3, true, 0));
  scene.meshes.push_back(sphere_mesh({-0.2, -0.1, -3.5}, 1.6, 3, false, 0));
  const surface::GpuSurfaceScene gpu = surface::upload(device(), scene);
  surface::ForwardPass pass(device());
  surface::ForwardSettings settings;
  settings.count_shading = true;
  const surface::ForwardImage image = surface::render_forward(device(), pass, gpu, scene.camera, {96, 80}, settings);
  size_t covered = 0, wrong = 0;
  for (size_t i = 0; i < image.shade_counts.size(); ++i) {
    const bool surface = image.rgba[i * 4 + 3] == 1.0f;
    covered += surface;
    if (image.shade_counts[i] != (surface ? 1u : 0u)) ++wrong;
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(covered, image.shade_counts.size() / 4);
  if (image.statistics) {
    EXPECT_EQ(image.fragment_invocations, covered);
  }
  std::printf("[ pre-pass ] %zu covered pixels, %zu with a shading count other than 1/0; pipeline statistics: %s %llu\n", covered,
              wrong, image.statistics ? "counted" : "not available", static_cast<unsigned long long>(image.fragment_invocations));
}

// A surface file has no lights; the renderers apply with_default_lighting, after which every
// covered pixel of the default material is at least 0.8 times the sky's least cosine mean.
TEST_F(ForwardTest, DefaultLightingMakesABareSurfaceVisible) {
  SurfaceMesh mesh = make_icosphere(glm::dvec3(-2.0, 5.0, 1.0), 0.5, 2);
  mesh.name = "bare.off";
  const SurfaceScene bare = make_surface_scene(mesh);
  const SurfaceScene lit = with_default_lighting(bare, bare.camera);
  const ForwardComparison r = compare(lit, 48, 48);
  expect_agreement(r, "default lighting");
  const double floor = 0.8 * (0.5 * (kDefaultSkyTop + kDefaultSkyBottom) - (kDefaultSkyTop - kDefaultSkyBottom) / 3.0);
  for (size_t i = 0; i < r.pixels; ++i)
    if (r.gpu.rgba[i * 4 + 3] == 1.0f) {
      for (int c = 0; c < 3; ++c) EXPECT_GE(r.gpu.rgba[i * 4 + c], floor * (1.0 - 1e-5)) << "pixel " << i;
    }
}

}  // namespace
}  // namespace prismoid::test
