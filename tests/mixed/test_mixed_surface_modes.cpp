// Every GPU surface mode around a volume (renderer/mixed): each backend draws its own depth
// pre-pass, and the volume's rays end at the depth read back from it. For each mode this device
// draws, with shadows and without:
//  - the depth equals the CPU reference's first hit (surface/depth_check.hpp: float and snapping
//    tolerances, +inf where nothing is hit, silhouettes left out);
//  - the volume's optical depth equals the one it has under the forward mode (the same geometry
//    rasterized the same way ends the rays at the same depths: within 2^-16 of the largest,
//    the interval stages' own float budget, plus where a depth differs by its tolerance);
//  - the composite is the rule applied to the mode's own surface colour (1e-6 relative: two
//    float operations).
// A mode the planner knows but a mixed scene cannot use (the CPU path tracer) is refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mixed/square_scene.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"
#include "support/gpu_fixture.hpp"
#include "surface/depth_check.hpp"
#include "surface/surface_test_scenes.hpp"

namespace prismoid {
namespace {

constexpr uint32_t kW = 48, kH = 36;

// A lit sphere inside a ball of constant extinction, over a floor seen at an angle, and a square
// in front of part of it.
SurfaceScene scene() {
  SurfaceScene s = test::sphere_scene({});
  s.meshes[0] = test::sphere_mesh({0.2, 0.0, 0.0}, 0.5, 2, true, 0);
  s.meshes.push_back(test::horizontal_quad("floor", 0.0, -1.2, 0.0, 5.0, 0));
  s.meshes.push_back(test::square_mesh({1.3, -0.9, -0.4, 0.2, 0.8}));
  return s;
}

Camera camera() {
  Camera c;
  c.eye = {0.8, 1.2, 3.6};
  c.target = {0.0, -0.2, 0.0};
  c.fovy_degrees = 50.0;
  c.near_distance = 0.05;
  return c;
}

// On the mesh backend (where the rays end does not depend on the volume's backend; test_mixed_frame
// and test_mixed_color hold both backends to the references).
class MixedSurfaceModesTest : public test::GpuTest {};

TEST_F(MixedSurfaceModesTest, EveryModesDepthEndsTheVolumeAsForwardDoes) {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 2, 0.8);
  const SurfaceScene surfaces = scene();
  mixed::MixedRenderer renderer(device(), ball, surfaces);
  frame::FrameSettings settings;
  settings.resolve.quantity = volume::Quantity::Transmittance;
  const uint32_t bits = device().capabilities().subpixel_precision_bits;
  const std::vector<bool> shadow_settings = renderer.surface_renderer().can_shadow() ? std::vector<bool>{false, true} : std::vector<bool>{false};
  for (const bool shadows : shadow_settings) {
    renderer.surface_renderer().set_shadows(shadows);
    const mixed::MixedFrame forward = renderer.render(camera(), settings, {kW, kH}, "forward");
    EXPECT_EQ(forward.shadows, shadows);
    double t_min = 1.0;
    for (float t : forward.volume.quantity) t_min = std::min(t_min, double(t));
    const double tau_max = -std::log(t_min);
    ASSERT_GT(tau_max, 0.5) << "the ball must absorb enough for the comparison to tell";
    for (const std::string& mode : renderer.surface_renderer().modes()) {
      const std::string what = mode + (shadows ? ", shadows" : ", no shadows");
      const mixed::MixedFrame f = renderer.render(camera(), settings, {kW, kH}, mode);
      EXPECT_EQ(f.surface_mode, mode);
      const test::DepthCheck c = test::check_depth(f.surface_depth, surfaces, camera(), kW, kH, bits);
      EXPECT_EQ(c.failures, 0u) << what << ": " << c.first_failure;
      EXPECT_GT(c.compared, size_t(kW) * kH / 3) << what;
      size_t differ = 0;
      double worst = 0.0;
      for (size_t i = 0; i < size_t(kW) * kH; ++i) {
        const double a = f.volume.quantity[i], b = forward.volume.quantity[i];
        ASSERT_TRUE(std::isfinite(a)) << what << ", pixel " << i;
        // Transmittance moves by at most the optical depth's change: the interval stages' budget,
        // plus the change the ray's end may make where the two depths differ at all.
        const double slack = f.surface_depth[i] == forward.surface_depth[i]
                                 ? 0.0
                                 : 0.8 * std::abs(double(f.surface_depth[i]) - double(forward.surface_depth[i]));
        const double tolerance = std::ldexp(1.0, -16) * std::max(tau_max, 1.0) + (std::isfinite(slack) ? slack : 1.0);
        differ += std::abs(a - b) > tolerance;
        worst = std::max(worst, std::abs(a - b));
        for (int k = 0; k < 3; ++k) {
          const double want = double(settings.resolve.medium[k]) * (1.0 - a) + a * double(f.surface_rgba[4 * i + k]);
          EXPECT_NEAR(f.display[4 * i + k], want, 1e-6 * std::max(1.0, std::abs(want))) << what << ", pixel " << i;
        }
      }
      EXPECT_EQ(differ, 0u) << what << ": the volume ends elsewhere than under forward";
      const bool planned_shadows = f.plan.surfaces.find(frame::PassId::ShadowRays) != nullptr;
      EXPECT_EQ(planned_shadows, f.shadows) << what;
      EXPECT_FALSE(f.plan.surfaces.passes.empty()) << what;
      std::printf("[ %s ] %zu depths within tolerance (worst at %.3f of it), %zu empty; transmittance within %.2g of forward's\n",
                  what.c_str(), c.compared, c.worst, c.empty, worst);
    }
  }
  EXPECT_THROW(renderer.render(camera(), settings, {kW, kH}, "path-reference"), InputError);
  EXPECT_THROW(renderer.render(camera(), settings, {kW, kH}, "no-such-mode"), InputError);
}

}  // namespace
}  // namespace prismoid
