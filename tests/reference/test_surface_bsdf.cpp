#include "renderer/reference/surface_bsdf.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "reference/ggx_albedo.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::reference {
namespace {

constexpr double kPi = std::numbers::pi;

glm::dvec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Midpoint quadrature over the upper hemisphere in (theta, phi); theta is split finer near the
// pole where GGX peaks.
template <typename F>
double hemisphere_integral(F f, int n_theta, int n_phi) {
  double sum = 0.0;
  for (int i = 0; i < n_theta; ++i) {
    // theta = (pi/2) s^2 puts more nodes near the pole; d theta = pi s ds.
    const double s = (i + 0.5) / n_theta;
    const double theta = 0.5 * kPi * s * s;
    const double dtheta = kPi * s / n_theta;
    for (int j = 0; j < n_phi; ++j) {
      const double phi = 2.0 * kPi * (j + 0.5) / n_phi;
      sum += f(direction(theta, phi)) * std::sin(theta) * dtheta * (2.0 * kPi / n_phi);
    }
  }
  return sum;
}

TEST(SurfaceBsdf, GgxDistributionProjectsToUnitArea) {
  // The microfacets' projected area equals the macro-surface's: integral D(m) cos(theta_m) = 1.
  for (double alpha : {0.05, 0.3, 1.0}) {
    const double area = hemisphere_integral([&](const glm::dvec3& m) { return ggx_d(m, alpha) * m.z; }, 4000, 8);
    EXPECT_NEAR(area, 1.0, 1e-5) << "alpha " << alpha;
  }
}

TEST(SurfaceBsdf, WeakWhiteFurnaceHoldsForSmithMasking) {
  // Heitz 2014, eq. 2 with G1: the visible projected microfacet area equals the macro-surface's
  // projected area, integral G1(wo) max(0, wo.m) D(m) d(omega_m) = cos(theta_o).
  for (double alpha : {0.1, 0.5, 1.0})
    for (double theta_o : {0.0, 0.7, 1.3, 1.55}) {
      const glm::dvec3 wo = direction(theta_o, 0.3);
      const double visible = hemisphere_integral(
          [&](const glm::dvec3& m) { return ggx_g1(wo, alpha) * std::max(0.0, glm::dot(wo, m)) * ggx_d(m, alpha); }, 3000, 256);
      EXPECT_NEAR(visible, wo.z, 2e-4) << "alpha " << alpha << " theta_o " << theta_o;
    }
}

TEST(SurfaceBsdf, VisibleNormalSamplesHaveTheMomentsOfTheirDensity) {
  // Moments of m under D_wo by quadrature against the sample means of 200k draws; a sampler
  // that does not follow ggx_visible_normal_pdf moves them by many standard errors.
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double alpha : {0.2, 0.8})
    for (double theta_o : {0.3, 1.2}) {
      const glm::dvec3 wo = direction(theta_o, 0.0);
      const int n = 200000;
      glm::dvec3 sum(0.0), sum2(0.0);
      for (int i = 0; i < n; ++i) {
        const glm::dvec3 m = sample_ggx_visible_normal(wo, alpha, u(gen), u(gen));
        ASSERT_NEAR(glm::length(m), 1.0, 1e-12);
        ASSERT_GE(m.z, 0.0);
        sum += m;
        sum2 += m * m;
      }
      const glm::dvec3 mean = sum / double(n);
      const glm::dvec3 se = glm::sqrt((sum2 / double(n) - mean * mean) / double(n));
      for (int k = 0; k < 3; ++k) {
        const double expected = hemisphere_integral(
            [&](const glm::dvec3& m) { return m[k] * ggx_visible_normal_pdf(wo, m, alpha); }, 3000, 256);
        EXPECT_NEAR(mean[k], expected, 5.0 * se[k] + 2e-4) << "alpha " << alpha << " theta_o " << theta_o << " axis " << k;
      }
    }
}

TEST(SurfaceBsdf, SampleWeightsEstimateTheAlbedoAndThePdfMatchesTheDraws) {
  // For a diffuse + specular material, the mean sample weight (f cos / pdf) estimates the
  // directional albedo, integral f cos, computed here by quadrature of bsdf_eval; the fraction
  // of draws that stay above the surface equals the quadrature of bsdf_pdf.
  const BsdfParams p = bsdf_params({0.5, 0.3, 0.1}, {0.3, 0.3, 0.3}, 0.5);
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (double theta_o : {0.2, 1.0, 1.45}) {
    const glm::dvec3 wo = direction(theta_o, 0.0);
    const int n = 200000;
    glm::dvec3 sum(0.0), sum2(0.0);
    int valid = 0;
    for (int i = 0; i < n; ++i) {
      const auto s = sample_bsdf(p, wo, u(gen), u(gen), u(gen));
      if (!s) continue;
      ASSERT_GT(s->pdf, 0.0);
      ASSERT_GT(s->wi.z, 0.0);
      ++valid;
      sum += s->weight;
      sum2 += s->weight * s->weight;
    }
    const glm::dvec3 mean = sum / double(n);
    const glm::dvec3 se = glm::sqrt((sum2 / double(n) - mean * mean) / double(n));
    for (int k = 0; k < 3; ++k) {
      const double albedo = hemisphere_integral([&](const glm::dvec3& wi) { return bsdf_eval(p, wo, wi)[k] * wi.z; }, 2000, 512);
      EXPECT_NEAR(mean[k], albedo, 5.0 * se[k] + 1e-3) << "theta_o " << theta_o << " channel " << k;
    }
    const double pdf_mass = hemisphere_integral([&](const glm::dvec3& wi) { return bsdf_pdf(p, wo, wi); }, 2000, 512);
    const double fraction = double(valid) / n;
    EXPECT_NEAR(pdf_mass, fraction, 5.0 * std::sqrt(fraction * (1.0 - fraction) / n) + 1e-3) << "theta_o " << theta_o;
    EXPECT_LE(pdf_mass, 1.0 + 1e-3);
  }
}

TEST(SurfaceBsdf, IsReciprocal) {
  std::mt19937_64 gen(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const BsdfParams p = bsdf_params({0.2, 0.5, 0.7}, {0.9, 0.5, 0.04}, 0.35);
  for (int i = 0; i < 1000; ++i) {
    const glm::dvec3 a = direction(0.5 * kPi * u(gen), 2.0 * kPi * u(gen));
    const glm::dvec3 b = direction(0.5 * kPi * u(gen), 2.0 * kPi * u(gen));
    const glm::dvec3 fab = bsdf_eval(p, a, b), fba = bsdf_eval(p, b, a);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(fab[k], fba[k], 1e-12 * std::max(1.0, std::abs(fab[k])));
  }
}

TEST(SurfaceBsdf, EvalIntegratesToTheIndependentGgxAlbedo) {
  // bsdf_eval (F0 = 1, no diffuse) integrated over wi equals the directional albedo computed
  // in half-vector space with the test's own Smith Lambda (tests/reference/ggx_albedo.hpp).
  for (double alpha : {1.0, 0.25})
    for (double mu : {1.0, 0.5, 0.1}) {
      const BsdfParams p{glm::dvec3(0.0), glm::dvec3(1.0), alpha};
      const glm::dvec3 wo(std::sqrt(1.0 - mu * mu), 0.0, mu);
      const double by_eval = hemisphere_integral([&](const glm::dvec3& wi) { return bsdf_eval(p, wo, wi).x * wi.z; }, 2000, 512);
      EXPECT_NEAR(by_eval, test::ggx_albedo_quadrature(mu, alpha), 3e-4) << "alpha " << alpha << " mu " << mu;
    }
}

TEST(SurfaceBsdf, SingleScatteringNeverReflectsMoreThanArrives) {
  // With F = 1 a single-scattering microfacet lobe reflects at most what arrives; the light
  // that would scatter between microfacets again is lost (Heitz, Hanika, d'Eon & Dachsbacher
  // 2016, "Multiple-scattering microfacet BSDFs with the Smith model"). The loss vanishes as
  // the surface becomes smooth and grows with roughness at normal incidence. At alpha = 1, D is
  // uniform (1/pi), so half of the D cos-weighted normals lie beyond 45 degrees and mirror
  // normal incidence below the horizon: E(normal) <= 1/2 exactly.
  double previous_normal = 1.0;
  for (double roughness : {0.0, 0.2, 0.5, 0.8, 1.0}) {
    const double alpha = std::max(roughness * roughness, kMinGgxAlpha);
    for (double mu : {1.0, 0.7, 0.4, 0.1}) {
      const double e = test::ggx_albedo_quadrature(mu, alpha);
      EXPECT_LE(e, 1.0 + 1e-6) << "roughness " << roughness << " mu " << mu;
      if (roughness == 0.0) {
        EXPECT_GT(e, 0.999) << mu;
      }
    }
    const double e_normal = test::ggx_albedo_quadrature(1.0, alpha);
    EXPECT_LE(e_normal, previous_normal + 1e-9) << roughness;
    previous_normal = e_normal;
    if (roughness == 1.0) {
      EXPECT_LE(e_normal, 0.5);
    }
    std::printf("GGX single-scattering albedo, roughness %.1f: E(mu=1) %.5f, E(mu=0.4) %.5f, E(mu=0.1) %.5f\n", roughness,
                e_normal, test::ggx_albedo_quadrature(0.4, alpha), test::ggx_albedo_quadrature(0.1, alpha));
  }
  // The quadrature has converged: doubling its resolution changes it by < 1e-4.
  EXPECT_NEAR(test::ggx_albedo_quadrature(0.3, 0.25), test::ggx_albedo_quadrature(0.3, 0.25, 4000, 512), 1e-4);
}

TEST(SurfaceBsdf, NeverReturnsNaNAtTheEdges) {
  const double tiny = std::numeric_limits<double>::denorm_min();
  const std::vector<glm::dvec3> dirs = {
      {0, 0, 1}, {1, 0, 0}, {0, 1, tiny}, glm::normalize(glm::dvec3(1, 1, 1e-300)), {0, 0, -1}, {0.6, 0, -0.8}};
  const double below_one = 1.0 - 0x1p-53;
  for (double roughness : {0.0, 1e-8, 0.5, 1.0}) {
    const BsdfParams p = bsdf_params(glm::dvec3(0.5), glm::dvec3(0.5), roughness);
    for (const auto& wo : dirs) {
      for (const auto& wi : dirs) {
        const glm::dvec3 f = bsdf_eval(p, wo, wi);
        EXPECT_TRUE(std::isfinite(f.x) && std::isfinite(f.y) && std::isfinite(f.z));
        EXPECT_TRUE(std::isfinite(bsdf_pdf(p, wo, wi)));
      }
      for (double a : {0.0, 0.5, below_one})
        for (double b : {0.0, 0.5, below_one})
          for (double c : {0.0, 0.5, below_one}) {
            const auto s = sample_bsdf(p, wo, a, b, c);
            if (!s) continue;
            EXPECT_TRUE(std::isfinite(s->pdf));
            EXPECT_TRUE(std::isfinite(s->weight.x) && std::isfinite(s->weight.y) && std::isfinite(s->weight.z));
            EXPECT_TRUE(std::isfinite(s->wi.x) && std::isfinite(s->wi.y) && std::isfinite(s->wi.z));
          }
    }
  }
  // A material that reflects nothing ends the path.
  EXPECT_FALSE(sample_bsdf(bsdf_params(glm::dvec3(0.0), glm::dvec3(0.0), 0.5), {0, 0, 1}, 0.5, 0.5, 0.5));
}

}  // namespace
}  // namespace prismoid::reference
