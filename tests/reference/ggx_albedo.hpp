#pragma once
// The directional albedo of a GGX lobe with Fresnel 1, E(theta_o) = integral of f cos over
// the hemisphere, by deterministic quadrature, written apart from the renderer's BSDF code
// (its own Smith Lambda, Heitz 2014 eq. 72) so that tests compare two independent routes.
//
// In half-vector form, d(omega_i) = 4 (wo.h) d(omega_h), so
//   E = integral D(h) G2(wo, wi(h)) (wo.h) / cos(theta_o) d(omega_h).
// With xi = tan^2(theta_h) / (alpha^2 + tan^2(theta_h)) (the GGX slope CDF),
// D(h) cos(theta_h) d(omega_h) = d(xi) d(phi) / (2 pi), which removes the peak of D:
//   E = 1/(2 pi) integral_0^1 integral_0^2pi G2 (wo.h) / (cos(theta_o) cos(theta_h)) d(phi) d(xi).
// The midpoint rule on an n_xi x n_phi grid; the integrand vanishes continuously where wi
// reaches the horizon (G2 -> 0), so the error falls quickly with n.
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace prismoid::test {

inline double smith_lambda_ggx(double cos_theta, double alpha) {
  if (cos_theta <= 0.0) return std::numeric_limits<double>::infinity();
  const double tan2 = (1.0 - cos_theta * cos_theta) / (cos_theta * cos_theta);
  return 0.5 * (-1.0 + std::sqrt(1.0 + alpha * alpha * tan2));
}

inline double ggx_albedo_quadrature(double cos_theta_o, double alpha, int n_xi = 2000, int n_phi = 256) {
  const double pi = std::numbers::pi;
  const glm::dvec3 wo(std::sqrt(std::max(0.0, 1.0 - cos_theta_o * cos_theta_o)), 0.0, cos_theta_o);
  const double lambda_o = smith_lambda_ggx(cos_theta_o, alpha);
  std::vector<double> cos_phi(static_cast<size_t>(n_phi)), sin_phi(static_cast<size_t>(n_phi));
  for (int j = 0; j < n_phi; ++j) {
    cos_phi[size_t(j)] = std::cos(2.0 * pi * (j + 0.5) / n_phi);
    sin_phi[size_t(j)] = std::sin(2.0 * pi * (j + 0.5) / n_phi);
  }
  double sum = 0.0;
  for (int i = 0; i < n_xi; ++i) {
    const double xi = (i + 0.5) / n_xi;
    const double tan_h = alpha * std::sqrt(xi / (1.0 - xi));
    const double cos_h = 1.0 / std::sqrt(1.0 + tan_h * tan_h);
    const double sin_h = tan_h * cos_h;
    for (int j = 0; j < n_phi; ++j) {
      const glm::dvec3 h(sin_h * cos_phi[size_t(j)], sin_h * sin_phi[size_t(j)], cos_h);
      const double wo_h = glm::dot(wo, h);
      if (wo_h <= 0.0) continue;
      const glm::dvec3 wi = 2.0 * wo_h * h - wo;
      if (wi.z <= 0.0) continue;
      const double g2 = 1.0 / (1.0 + lambda_o + smith_lambda_ggx(wi.z, alpha));
      sum += g2 * wo_h / (cos_theta_o * cos_h);
    }
  }
  return sum / (double(n_xi) * n_phi);
}

}  // namespace prismoid::test
