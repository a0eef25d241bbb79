// The analytic fields marching samples (renderer/volume/analytic_field.*), on the CPU: the
// gradient the isosurface shades with, and the second-derivative bound the marching tests
// derive their step tolerances from. (That the GLSL twin agrees is covered by the GPU tests.)
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

#include "renderer/volume/analytic_field.hpp"

namespace prismoid {
namespace {

constexpr double kPi = std::numbers::pi;

// Rounding of one evaluation (absolute): the largest terms are Marschner-Lobb's cosine
// argument 2 pi f_M cos(.) <= 38, carrying ~4 roundings (2^-53 relative) that reach the
// value through alpha / (2 (1 + alpha)) = 0.1, i.e. ~2^-49; and for the blobs exp(-a) with an
// argument a of a few roundings, an error of a e^-a * 2^-51 <= 2^-52 per blob. 2^-46 is 8x
// above the larger. The gradient's components (<= 7 in size) carry at most 16x that.
constexpr double kValueRounding = 0x1p-46;
constexpr double kGradientRounding = 0x1p-42;

// An upper bound, over all points and unit directions u, of |d^3/ds^3 f(p + s u)|.
//  - Gaussian blob exp(-|d|^2 / (2 w^2)): along u it is exp(-b^2 / (2 w^2)) phi((t0 + s) / w)
//    with phi(t) = exp(-t^2 / 2), whose third derivative -(t^3 - 3 t) phi(t) is largest in
//    size at t^2 = 3 - sqrt(6) (the roots of t^4 - 6 t^2 + 3): sqrt(6) sqrt(3 - sqrt(6))
//    exp(-(3 - sqrt(6)) / 2) ~ 1.380; so the bound is that over w^3, summed over blobs.
//  - Marschner-Lobb (f_M, alpha): A(z) + beta cos(k C(x, y)) with C = cos(a r), a = pi / 2,
//    k = 2 pi f_M, beta = alpha / (2 (1 + alpha)), |A'''| <= a^3 / (2 (1 + alpha)). Along a
//    line in (x, y) at angle theta to the radius, C' = -a sin(a r) cos(theta) (<= a), C'' has
//    the Hessian's eigenvalues -a^2 cos(a r) and -a sin(a r) / r (<= a^2), and
//    C''' = F''' c^3 + 3 c (1 - c^2) (F'' / r - F' / r^2) for F(r) = cos(a r), c = cos(theta):
//    F''' = a^3 sin(a r) and F'' / r - F' / r^2 = a^3 (sin x - x cos x) / x^2 (x = a r), where
//    |sin x - x cos x| = |int_0^x t sin t dt| <= x^2 / 2; c^3 + 1.5 c (1 - c^2) <= 1 on [0, 1],
//    so |C'''| <= a^3. Then (cos(k C))''' = k^3 sin C'^3 - 3 k^2 cos C' C'' - k sin C''' is at
//    most a^3 (k^3 + 3 k^2 + k).
double third_derivative_bound(const volume::AnalyticField& field) {
  switch (field.kind) {
    case volume::FieldKind::Linear: return 0.0;
    case volume::FieldKind::MarschnerLobb: {
      const double f_m = field.params[0].x, alpha = field.params[0].y;
      const double a = kPi / 2.0, k = 2.0 * kPi * f_m, beta = alpha / (2.0 * (1.0 + alpha));
      return beta * a * a * a * (k * k * k + 3.0 * k * k + k) + a * a * a / (2.0 * (1.0 + alpha));
    }
    case volume::FieldKind::GaussianBlobs: {
      const double t2 = 3.0 - std::sqrt(6.0);
      const double phi3 = std::sqrt(6.0) * std::sqrt(t2) * std::exp(-t2 / 2.0);
      double sum = 0.0;
      for (const glm::dvec4& b : field.params) sum += phi3 / (b.w * b.w * b.w);
      return sum;
    }
    case volume::FieldKind::Grid: break;  // not smooth across voxel faces: no bound
  }
  return std::numeric_limits<double>::infinity();
}

// Many points of [-1.5, 1.5]^3 (beyond the box the fields are drawn in), plus the special
// ones: the z axis (Marschner-Lobb's r = 0 branch) and each parameter vector's centre.
std::vector<glm::dvec3> sample_points(const volume::AnalyticField& field, size_t count) {
  std::mt19937_64 rng(20240611);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  std::vector<glm::dvec3> points = {glm::dvec3(0.0), glm::dvec3(0.0, 0.0, 0.7), glm::dvec3(1e-9, -1e-9, -0.3)};
  for (const glm::dvec4& p : field.params) points.push_back(glm::dvec3(p));
  while (points.size() < count) points.push_back({u(rng), u(rng), u(rng)});
  return points;
}

constexpr std::array<glm::dvec3, 3> kAxes = {glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1)};

// Central differences: (f(p + h e) - f(p - h e)) / 2h - f'(p) = h^2 / 6 f'''(xi) (Taylor
// with the mean value), plus the two evaluations' rounding over 2h. h = 1e-5 puts the
// truncation for Marschner-Lobb (f''' <= 2.3e4) at 4e-7, rounding at 1.4e-9: a gradient off
// by any term's factor (components up to ~7) is far outside.
TEST(AnalyticField, GradientMatchesCentralDifferences) {
  const double h = 1e-5;
  for (const std::string& name : volume::field_names()) {
    const volume::AnalyticField field = volume::field_from_name(name);
    const double tol = h * h / 6.0 * third_derivative_bound(field) + kValueRounding / h;
    double worst = 0.0, largest = 0.0;
    for (const glm::dvec3& p : sample_points(field, 2000)) {
      const glm::dvec3 g = volume::gradient(field, p);
      for (int i = 0; i < 3; ++i) {
        const double fd = (volume::evaluate(field, p + h * kAxes[i]) - volume::evaluate(field, p - h * kAxes[i])) / (2.0 * h);
        worst = std::max(worst, std::abs(fd - g[i]) / tol);
        largest = std::max(largest, std::abs(g[i]));
        ASSERT_NEAR(g[i], fd, tol) << name << " at (" << p.x << ", " << p.y << ", " << p.z << "), component " << i;
      }
    }
    EXPECT_GT(largest, 0.1) << name << ": the gradient must be exercised";
    std::printf("%s: gradient within %.3g of central differences, worst at %.3f of it\n", name.c_str(), tol, worst);
  }
}

// Largest |eigenvalue| of a symmetric 3x3 matrix (its spectral norm), by cyclic Jacobi.
double spectral_norm(std::array<std::array<double, 3>, 3> a) {
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
    if (off < 1e-30 * (a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2]) || off == 0.0) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < 3; ++k) {  // columns p, q of a J
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {  // rows p, q of J^T (a J)
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
      }
  }
  return std::max({std::abs(a[0][0]), std::abs(a[1][1]), std::abs(a[2][2])});
}

// second_derivative_bound(f) claims |u^T H u| <= B everywhere, i.e. the Hessian's spectral
// norm never exceeds B. The Hessian is estimated by central differences of the (tested)
// analytic gradient: column i is (grad(p + h e_i) - grad(p - h e_i)) / 2h, the mean of
// H(p + t e_i) e_i over |t| <= h, which differs from H(p) e_i by at most h / 2 times the
// third-derivative bound (the norm of a symmetric trilinear form is its largest diagonal
// value), plus sqrt(3) kGradientRounding / h of rounding. Over three columns the Frobenius
// norm (>= the spectral norm) of the error is at most sqrt(3) times that; symmetrizing does
// not increase it. The bound must also be useful: within 4x of the largest sampled norm, or
// the marching tolerances built on it say little.
TEST(AnalyticField, SecondDerivativeBoundHoldsEverywhereSampled) {
  const double h = 1e-6;
  for (const std::string& name : volume::field_names()) {
    const volume::AnalyticField field = volume::field_from_name(name);
    const double bound = volume::second_derivative_bound(field);
    const double fd_error = std::sqrt(3.0) * (h / 2.0 * third_derivative_bound(field) + std::sqrt(3.0) * kGradientRounding / h);
    double largest = 0.0;
    for (const glm::dvec3& p : sample_points(field, 20000)) {
      std::array<glm::dvec3, 3> column;
      for (int i = 0; i < 3; ++i)
        column[i] = (volume::gradient(field, p + h * kAxes[i]) - volume::gradient(field, p - h * kAxes[i])) / (2.0 * h);
      std::array<std::array<double, 3>, 3> hessian;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) hessian[i][j] = 0.5 * (column[j][i] + column[i][j]);
      const double norm = spectral_norm(hessian);
      largest = std::max(largest, norm);
      ASSERT_LE(norm, bound + fd_error) << name << " at (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
    if (field.kind == volume::FieldKind::Linear) EXPECT_LE(largest, fd_error) << name;
    else EXPECT_GE(largest, bound / 4.0) << name << ": the bound is far above any Hessian sampled";
    std::printf("%s: largest sampled Hessian norm %.4g, bound %.4g (finite-difference error %.2g)\n", name.c_str(), largest,
                bound, fd_error);
  }
}

// Moving a field's coordinates (what marching uploads, relative to the mesh's centre) keeps
// its values: g(q) = f(q + origin), up to the rounding of q + origin (2^-53 of 1e5 times
// |grad f| <= 7) and of the moved parameters, far below 1e-9. Marschner-Lobb has no position.
TEST(AnalyticField, TranslatedFieldKeepsItsValues) {
  const glm::dvec3 origin(1e5 + 0.3, -1e5 + 0.1, 1e5 - 0.2);
  for (const std::string& name : volume::field_names()) {
    volume::AnalyticField field = volume::field_from_name(name);
    for (glm::dvec4& p : field.params)  // put the field near `origin` (linear fields are everywhere)
      if (field.kind == volume::FieldKind::GaussianBlobs) p = glm::dvec4(glm::dvec3(p) + origin, p.w);
    const auto moved = volume::translated(field, origin);
    if (field.kind == volume::FieldKind::MarschnerLobb) {
      EXPECT_FALSE(moved.has_value());
      continue;
    }
    ASSERT_TRUE(moved.has_value()) << name;
    for (const glm::dvec3& q : sample_points(volume::field_from_name(name), 200)) {
      const double f = volume::evaluate(field, q + origin);
      EXPECT_NEAR(volume::evaluate(*moved, q), f, 1e-9 * (1.0 + std::abs(f))) << name;
      const glm::dvec3 dg = volume::gradient(*moved, q) - volume::gradient(field, q + origin);
      EXPECT_LT(glm::length(dg), 1e-8) << name;
    }
  }
}

// The spectral norm itself: a rotated diagonal matrix has its largest |diagonal| value.
TEST(AnalyticField, SpectralNormOfARotatedDiagonalMatrix) {
  const double c = std::cos(0.7), s = std::sin(0.7);
  const glm::dmat3 r = glm::dmat3(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0) * glm::dmat3(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c);
  const glm::dmat3 m = r * glm::dmat3(2.0, 0.0, 0.0, 0.0, -5.0, 0.0, 0.0, 0.0, 3.0) * glm::transpose(r);
  std::array<std::array<double, 3>, 3> a;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) a[i][j] = m[j][i];
  EXPECT_NEAR(spectral_norm(a), 5.0, 1e-12);
}

}  // namespace
}  // namespace prismoid
