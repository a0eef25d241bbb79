// The forward passes' depth buffer read back (issue "A volume inside its geometry", step 1): per
// pixel the nearest surface's depth along the viewing axis, what a volume's rays will end at,
// against the CPU reference's first hit, plain and shadowed forward (tolerances: depth_check.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "scene/surface_generators.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/depth_check.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

class ForwardDepthTest : public GpuTest {
 protected:
  void expect(const DepthCheck& c, const std::string& what, size_t pixels) {
    EXPECT_EQ(c.failures, 0u) << what << ": " << c.first_failure;
    EXPECT_GT(c.compared, pixels / 4) << what;
    std::printf("[ %s ] %zu depths within tolerance (worst at %.3f of it), %zu empty pixels +inf\n", what.c_str(), c.compared, c.worst,
                c.empty);
  }
};

// Two spheres, one behind the other, and a floor seen at a grazing angle (its depth gradient
// large); the Cornell box, whose walls meet the sky nowhere. Plain forward.
TEST_F(ForwardDepthTest, PlainForwardDepthIsTheReferencesFirstHit) {
  SurfaceScene spheres = sphere_scene({});
  spheres.meshes.push_back(sphere_mesh({0.9, 0.3, -1.5}, 0.8, 3, true, 0));
  spheres.meshes.push_back(horizontal_quad("floor", 0.0, -1.0, 0.0, 6.0, 0));
  const uint32_t w = 160, h = 120;
  surface::ForwardPass pass(device());
  surface::ForwardSettings settings;
  settings.read_depth = true;
  for (const SurfaceScene& scene : {spheres, make_cornell_box()}) {
    const surface::GpuSurfaceScene gpu = surface::upload(device(), scene);
    const surface::ForwardImage image = surface::render_forward(device(), pass, gpu, scene.camera, {w, h}, settings);
    ASSERT_EQ(image.depth.size(), size_t(w) * h);
    expect(check_depth(image.depth, scene, scene.camera, w, h, device().capabilities().subpixel_precision_bits), scene.name, size_t(w) * h);
  }
  // Without read_depth nothing is read.
  const surface::GpuSurfaceScene gpu = surface::upload(device(), spheres);
  EXPECT_TRUE(surface::render_forward(device(), pass, gpu, spheres.camera, {w, h}).depth.empty());
}

// The shadowed forward pass keeps its own pre-pass: the same depths.
TEST_F(ForwardDepthTest, ShadowedForwardDepthIsTheReferencesFirstHit) {
  if (!device().ray_tracing_enabled()) GTEST_SKIP() << "no ray tracing on " << device().capabilities().name;
  const SurfaceScene scene = make_cornell_box();
  const uint32_t w = 160, h = 120;
  surface::ShadowedForwardPass pass(device());
  const surface::GpuSurfaceScene gpu = surface::upload(device(), scene);
  const rt::SceneAccel accel(device(), scene);
  surface::ForwardSettings settings;
  settings.read_depth = true;
  const surface::ForwardImage image = surface::render_forward_shadowed(device(), pass, gpu, accel, scene.camera, {w, h}, settings);
  expect(check_depth(image.depth, scene, scene.camera, w, h, device().capabilities().subpixel_precision_bits), "Cornell box, shadowed",
         size_t(w) * h);
}

}  // namespace
}  // namespace prismoid::test
