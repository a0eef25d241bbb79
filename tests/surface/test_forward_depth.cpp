// The forward passes' depth buffer read back (issue "A volume inside its geometry", step 1): per
// pixel the nearest surface's depth along the viewing axis, what a volume's rays will end at,
// against the CPU reference's first hit (reference::direct_light_image: the ray parameter of a
// unit ray times its cosine to the viewing axis), plain and shadowed forward.
//
// Tolerance per pixel, from the two error sources:
//  1. The rasterizer snaps vertices to 2^-b pixel (b = subPixelPrecisionBits; each moves by at
//     most 2^-(b+1) per axis), so the surface under the pixel centre moves across the view by as
//     much: the depth changes by at most its screen gradient times that, per axis. The gradient is
//     the larger one-sided difference of the reference's depths at the neighbours on the same
//     mesh; the bound takes 2^-b (a factor 2 for the differences' curvature).
//  2. float: positions and matrices rounded (2^-24 relative each, a few terms), the stored
//     z = near / d (2^-24), its interpolation across the triangle (a few ulp): 2^-20 of d in all,
//     the 1e-6.
// Pixels next to a silhouette (a neighbour that hits another mesh or nothing) are not compared:
// there the snapped edge decides which surface the centre sees. Where the reference hits
// nothing and no neighbour does, the depth must be +inf.
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
#include "surface/surface_test_scenes.hpp"

namespace prismoid::test {
namespace {

struct DepthCheck {
  size_t compared = 0, empty = 0, failures = 0;
  double worst = 0.0;  // largest error over its tolerance
  std::string first_failure;
};

DepthCheck check_depth(const std::vector<float>& gpu, const SurfaceScene& scene, const Camera& camera, uint32_t w, uint32_t h,
                       uint32_t subpixel_bits) {
  const reference::DirectLightImage ref = reference::direct_light_image(scene, camera, w, h);
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  std::vector<double> d(size_t(w) * h, std::numeric_limits<double>::infinity());
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const auto& s = ref.pixels[size_t(y) * w + x];
      if (s.hit) d[size_t(y) * w + x] = s.t * glm::dot(reference::ray_direction(camera, w, h, x + 0.5, y + 0.5), forward);
    }
  const double snap = std::ldexp(1.0, -int(subpixel_bits));
  DepthCheck c;
  EXPECT_EQ(gpu.size(), d.size());
  for (uint32_t y = 1; y + 1 < h; ++y)
    for (uint32_t x = 1; x + 1 < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const auto& s = ref.pixels[i];
      bool edge = false;
      double gx = 0.0, gy = 0.0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const size_t j = size_t(int(y) + dy) * w + size_t(int(x) + dx);
          const auto& n = ref.pixels[j];
          if (n.hit != s.hit || (s.hit && n.mesh != s.mesh)) edge = true;
          if (!s.hit || !n.hit) continue;
          if (dy == 0 && dx != 0) gx = std::max(gx, std::abs(d[j] - d[i]));
          if (dx == 0 && dy != 0) gy = std::max(gy, std::abs(d[j] - d[i]));
        }
      if (edge) continue;
      const double g = gpu[i];
      if (!s.hit) {
        ++c.empty;
        if (!(std::isinf(g) && g > 0.0) && c.failures++ == 0)
          c.first_failure = "pixel (" + std::to_string(x) + "," + std::to_string(y) + ") sees nothing, depth " + std::to_string(g);
        continue;
      }
      ++c.compared;
      const double tolerance = std::ldexp(1.0, -20) * d[i] + snap * (gx + gy);
      const double error = std::abs(g - d[i]);
      if (!(error <= tolerance)) {
        if (c.failures++ == 0)
          c.first_failure = "pixel (" + std::to_string(x) + "," + std::to_string(y) + "): depth " + std::to_string(g) + ", reference " +
                            std::to_string(d[i]) + ", tolerance " + std::to_string(tolerance);
      } else {
        c.worst = std::max(c.worst, error / tolerance);
      }
    }
  return c;
}

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
