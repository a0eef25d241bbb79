#pragma once
// A surface backend's depth buffer read back (view_depth.hpp): per pixel the nearest surface's
// depth along the viewing axis, what a volume's rays end at, against the CPU reference's first hit
// (reference::direct_light_image: the ray parameter of a unit ray times its cosine to the
// viewing axis).
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
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::test {

struct DepthCheck {
  size_t compared = 0, empty = 0, failures = 0;
  double worst = 0.0;  // largest error over its tolerance
  std::string first_failure;
};

inline DepthCheck check_depth(const std::vector<float>& gpu, const SurfaceScene& scene, const Camera& camera, uint32_t w, uint32_t h,
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

}  // namespace prismoid::test
