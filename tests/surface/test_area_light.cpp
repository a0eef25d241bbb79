// The geometry of area lights (renderer/reference/area_light) and the float atan the shaders use
// (shaders/shared/surface_math.h), against closed forms and independent integrals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>

#include "renderer/reference/area_light.hpp"
#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/surface_bsdf.hpp"
#include "shaders/shared/surface_math.h"

namespace prismoid::reference {
namespace {

constexpr double kPi = std::numbers::pi;

// The float atan2 is used for angles and solid angles on the GPU. Its error, measured here over
// a dense sweep of directions and of small angles, is what the GPU tolerances assume: at most
// 4 units in the last place of the result (2^-21 relative) plus 2^-24 absolute.
TEST(SurfaceMath, FloatAtan2IsWithinFourUlpsOfTheTrueAngle) {
  double worst = 0.0;
  auto check = [&](float y, float x) {
    const double exact = std::atan2(double(y), double(x));
    const double got = double(gpu::prismoid_atan2_upper(y, x));
    const double bound = 4.0 * 0x1p-24 * std::abs(exact) + 0x1p-24;
    worst = std::max(worst, std::abs(got - exact) / bound);
  };
  const int n = 200000;
  for (int i = 0; i <= n; ++i) {
    const double a = kPi * i / n;
    check(float(std::sin(a)), float(std::cos(a)));
  }
  for (int e = -40; e <= 0; ++e)  // small angles: relative accuracy matters
    for (int k = 1; k < 64; ++k) {
      const float y = std::ldexp(float(k) / 64.0f, e);
      check(y, 1.0f);
      check(y, -1.0f);
      check(1.0f, y);
    }
  EXPECT_LE(worst, 1.0) << "worst error in units of the bound";
  EXPECT_EQ(gpu::prismoid_atan2_upper(0.0f, 0.0f), 0.0f);
  EXPECT_EQ(gpu::prismoid_atan2_upper(0.0f, -1.0f), 3.1415927f);
}

TEST(AreaLight, OctantTriangleSubtendsAnEighthOfTheSphere) {
  const glm::dvec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  EXPECT_NEAR(triangle_solid_angle(x, y, z), kPi / 2.0, 1e-14);
  double total = 0.0;
  for (double sx : {-1.0, 1.0})
    for (double sy : {-1.0, 1.0})
      for (double sz : {-1.0, 1.0}) total += triangle_solid_angle(sx * x, sy * y, sz * z);
  EXPECT_NEAR(total, 4.0 * kPi, 1e-13);
  // Projected solid angle of the octant about z: the integral of cos over it is pi / 4.
  EXPECT_NEAR(projected_solid_angle({x, y, z}, z).value, kPi / 4.0, 1e-14);
}

// Lambert's closed form equals the adaptive integral of dot(n, w) for random triangles, near
// and far (small); for triangles across the horizon, the parts clipped to either side give the
// integral's positive and negative parts.
TEST(AreaLight, ProjectedSolidAngleMatchesAdaptiveIntegral) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int straddling = 0;
  for (int i = 0; i < 200; ++i) {
    const glm::dvec3 n = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const double distance = i % 4 == 0 ? 30.0 : 1.5;
    const glm::dvec3 c = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)) + 0.2 * n) * distance;
    auto corner = [&] { return c + 0.6 * glm::dvec3(u(rng), u(rng), u(rng)); };  // at least 0.46 from the origin
    const Polygon tri{corner(), corner(), corner()};
    const Polygon above = clip_to_hemisphere(tri, n), below = clip_to_hemisphere(tri, -n);
    if (above.size() >= 3 && below.size() >= 3) ++straddling;
    const double closed = projected_solid_angle(above, n).value - projected_solid_angle(below, -n).value;
    const double numeric = adaptive_integral(tri, [&](const glm::dvec3& w) { return glm::dvec3(glm::dot(n, w)); }, 1e-13).x;
    const double scale = std::max(projected_solid_angle(tri, n).abs_sum, 1e-6);
    EXPECT_NEAR(closed, numeric, 1e-10 * scale) << "triangle " << i;
    // The clipped part alone: the integral of max(0, n.w), smooth over it.
    if (above.size() >= 3) {
      const double positive =
          adaptive_integral(above, [&](const glm::dvec3& w) { return glm::dvec3(std::max(0.0, glm::dot(n, w))); }, 1e-13).x;
      EXPECT_NEAR(projected_solid_angle(above, n).value, positive, 1e-10 * scale) << "triangle " << i;
    }
  }
  EXPECT_GT(straddling, 20) << "of 200";  // the horizon was crossed often enough to test the clipping
}

// The sky's closed form against the hemisphere integrated as the four octant triangles about n.
TEST(AreaLight, SkyCosineMeanMatchesHemisphereIntegral) {
  const Sky sky{{0.9, 0.5, 0.3}, {0.1, 0.2, 0.05}, glm::normalize(glm::dvec3(0.2, 1.0, -0.3))};
  for (const glm::dvec3 n0 : {glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::dvec3(1, 0.3, 0.2), glm::dvec3(-0.4, 0.1, 0.9)}) {
    const glm::dvec3 n = glm::normalize(n0);
    const glm::dvec3 t = glm::normalize(glm::cross(n, glm::dvec3(0.3, 0.5, 0.7)));
    const glm::dvec3 b = glm::cross(n, t);
    glm::dvec3 integral(0.0);
    const glm::dvec3 rim[4] = {t, b, -t, -b};
    for (int k = 0; k < 4; ++k)
      integral += adaptive_integral({rim[k], rim[(k + 1) % 4], n},
                                    [&](const glm::dvec3& w) { return sky.radiance(w) * std::max(0.0, glm::dot(n, w)); }, 1e-12);
    const glm::dvec3 closed = sky_cosine_mean(sky, n);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(closed[c], integral[c] / kPi, 1e-9);
  }
}

// The forward rule for the GGX lobe: its error falls by about 4 when n doubles (second order),
// and at n = 16 it is within 1e-3 of the exact integral.
TEST(AreaLight, SubdivisionRuleConvergesAtSecondOrder) {
  const BsdfParams p = bsdf_params(glm::dvec3(0.0), glm::dvec3(0.5), 0.5);
  const glm::dvec3 n(0, 0, 1);
  const glm::dvec3 wo = glm::normalize(glm::dvec3(0.6, 0.0, 0.8));
  const DirectionalIntegrand f = [&](const glm::dvec3& w) { return bsdf_eval(p, wo, w) * std::max(0.0, w.z); };
  const Polygon light{{-1.0, -0.3, 1.0}, {-0.4, -0.3, 1.2}, {-0.6, 0.4, 1.1}};
  const double exact = adaptive_integral(light, f, 1e-13).x;
  double previous = 0.0;
  for (uint32_t k : {2u, 4u, 8u, 16u}) {
    const double error = std::abs(subdivision_rule(light, k, f).x - exact);
    if (k > 2) {
      EXPECT_GT(previous / error, 3.0) << "n = " << k;
      EXPECT_LT(previous / error, 5.0) << "n = " << k;
    }
    previous = error;
  }
  EXPECT_LT(previous, 1e-3 * exact);
}

}  // namespace
}  // namespace prismoid::reference
