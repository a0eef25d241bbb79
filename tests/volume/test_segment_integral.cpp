// The exact segment integral and the pre-integration table, against closed forms and an
// independent quadrature.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "renderer/volume/segment_integral.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/input_error.hpp"

namespace prismoid::volume {
namespace {

TransferFunction flat(glm::dvec3 rgb, double opacity, double density) {
  TransferFunction tf;
  tf.name = "flat";
  tf.color = {{0.0, rgb}};
  tf.opacity = {{0.0, opacity}};
  tf.density_scale = density;
  return tf;
}

// Composite Simpson on the emission-absorption integral, evaluated straight from its
// definition (no integration by parts, no Gauss-Legendre): an independent check of the
// closed form. The grid is split where x crosses a transfer-function point, so each step sees
// smooth integrands: Simpson's error is O(h^4) (h <= 1e-4 here: below 1e-13), and tau by the
// trapezoid rule is exact because sigma is linear within a step.
SegmentRadiance simpson(const std::vector<TfSample>& tf, double xf, double xb, double length) {
  std::vector<double> cuts{0.0, 1.0};
  for (const auto& s : tf)
    if (xb != xf && (s.x - xf) / (xb - xf) > 0.0 && (s.x - xf) / (xb - xf) < 1.0) cuts.push_back((s.x - xf) / (xb - xf));
  std::sort(cuts.begin(), cuts.end());
  auto sample = [&](double u) { return evaluate(tf, xf + (xb - xf) * u); };
  double tau = 0.0;
  glm::dvec3 c(0.0);
  for (size_t k = 1; k < cuts.size(); ++k) {
    const int n = std::max(1, int(std::ceil((cuts[k] - cuts[k - 1]) * length / 1e-4)));
    const double du = (cuts[k] - cuts[k - 1]) / n, h = du * length;
    for (int i = 0; i < n; ++i) {
      const double u0 = cuts[k - 1] + i * du;
      const TfSample a = sample(u0), m = sample(u0 + 0.5 * du), b = sample(u0 + du);
      const double tau_m = tau + 0.5 * h * 0.5 * (a.sigma + m.sigma);
      const double tau_b = tau + 0.5 * h * (a.sigma + 2.0 * m.sigma + b.sigma) * 0.5;
      c += h / 6.0 * (a.sigma * a.rgb * std::exp(-tau) + 4.0 * m.sigma * m.rgb * std::exp(-tau_m) + b.sigma * b.rgb * std::exp(-tau_b));
      tau = tau_b;
    }
  }
  return {c, 1.0 - std::exp(-tau)};
}

TEST(SegmentIntegral, ConstantMediumMatchesClosedForm) {
  const glm::dvec3 rgb(0.2, 0.5, 0.9);
  const auto tf = breakpoints(flat(rgb, 0.8, 2.5));
  for (double length : {0.0, 1e-9, 0.01, 0.3, 1.0, 7.0, 100.0}) {
    const SegmentRadiance r = integrate_segment(tf, 0.3, 0.3, length);
    const double alpha = 1.0 - std::exp(-2.0 * length);  // sigma = 2.5 * 0.8
    EXPECT_NEAR(r.alpha, alpha, 1e-15) << length;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.color[c], rgb[c] * alpha, 1e-15) << length;
  }
}

TEST(SegmentIntegral, LinearExtinctionConstantColourMatchesClosedForm) {
  // Opacity ramp 0..1 over x, density 3: sigma(x) = 3x; with constant colour C = c * alpha and
  // alpha = 1 - exp(-L * mean sigma).
  TransferFunction tf = flat({0.7, 0.1, 0.4}, 0.0, 3.0);
  tf.opacity = {{0.0, 0.0}, {1.0, 1.0}};
  const auto samples = breakpoints(tf);
  for (auto [xf, xb, len] : {std::tuple{0.0, 1.0, 2.0}, {0.9, 0.2, 0.5}, {0.5, 0.5, 3.0}, {1.0, 0.0, 40.0}}) {
    const SegmentRadiance r = integrate_segment(samples, xf, xb, len);
    const double alpha = 1.0 - std::exp(-len * 1.5 * (xf + xb));
    EXPECT_NEAR(r.alpha, alpha, 1e-14);
    EXPECT_NEAR(r.color.r, 0.7 * alpha, 1e-14);
    EXPECT_NEAR(r.color.b, 0.4 * alpha, 1e-14);
  }
}

TEST(SegmentIntegral, PiecewiseTransferFunctionMatchesIndependentQuadrature) {
  TransferFunction tf = preset("viridis");
  tf.opacity = {{0.0, 0.0}, {0.3, 0.9}, {0.55, 0.1}, {1.0, 0.6}};
  tf.density_scale = 4.0;
  const auto samples = breakpoints(tf);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.2, 1.2);  // also beyond the range (clamped)
  for (int i = 0; i < 25; ++i) {
    const double xf = u(rng), xb = u(rng), len = 0.05 + 2.0 * std::abs(u(rng));
    const SegmentRadiance exact = integrate_segment(samples, xf, xb, len);
    const SegmentRadiance check = simpson(samples, xf, xb, len);
    EXPECT_NEAR(exact.alpha, check.alpha, 1e-12) << xf << " " << xb << " " << len;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(exact.color[c], check.color[c], 1e-12) << xf << " " << xb << " " << len;
  }
}

TEST(SegmentIntegral, SplittingASegmentAndCompositingChangesNothing) {
  // Emission-absorption is additive along a ray: front part composited over back part.
  TransferFunction tf = preset("cool-to-warm");
  tf.density_scale = 6.0;
  const auto samples = breakpoints(tf);
  const double xf = 0.05, xb = 0.93, len = 1.7;
  for (double split : {0.1, 0.37, 0.5, 0.88}) {
    const double xm = xf + split * (xb - xf);
    const SegmentRadiance whole = integrate_segment(samples, xf, xb, len);
    const SegmentRadiance parts =
        composite(integrate_segment(samples, xf, xm, split * len), integrate_segment(samples, xm, xb, (1.0 - split) * len));
    EXPECT_NEAR(whole.alpha, parts.alpha, 1e-14);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(whole.color[c], parts.color[c], 1e-14);
  }
  // Reversing the direction changes the colour (emission is order dependent) but not alpha.
  const SegmentRadiance forward = integrate_segment(samples, xf, xb, len), backward = integrate_segment(samples, xb, xf, len);
  EXPECT_NEAR(forward.alpha, backward.alpha, 1e-14);
  EXPECT_GT(std::abs(forward.color.r - backward.color.r), 1e-3);
}

TEST(SegmentIntegral, ZeroExtinctionEmitsNothing) {
  const auto samples = breakpoints(flat({1, 1, 1}, 0.0, 10.0));
  const SegmentRadiance r = integrate_segment(samples, 0.0, 1.0, 5.0);
  EXPECT_EQ(r.alpha, 0.0);
  EXPECT_NEAR(r.color.g, 0.0, 1e-16);
}

TEST(PreintegrationTable, ExactAtTexelsAndSecondOrderBetween) {
  TransferFunction tf = preset("viridis");
  tf.opacity = {{0.0, 0.0}, {0.4, 1.0}, {1.0, 0.3}};
  tf.density_scale = 3.0;
  const auto samples = breakpoints(tf);
  const double max_length = 0.8;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::array<double, 3>> points(3000);
  for (auto& p : points) p = {u(rng), u(rng), u(rng) * max_length};
  double previous = 0.0;
  for (uint32_t size : {8u, 16u, 32u, 64u}) {
    const PreintegrationTable table = build_preintegration_table(samples, size, max_length);
    // At texel centres the lookup returns the stored float of the exact value.
    const SegmentRadiance at = lookup(table, 3.0 / (size - 1), 5.0 / (size - 1), 2.0 / (size - 1) * max_length);
    const SegmentRadiance exact_at = integrate_segment(samples, 3.0 / (size - 1), 5.0 / (size - 1), 2.0 / (size - 1) * max_length);
    EXPECT_NEAR(at.alpha, exact_at.alpha, 1e-7);
    double worst = 0.0;
    for (const auto& p : points) {
      const SegmentRadiance e = integrate_segment(samples, p[0], p[1], p[2]), l = lookup(table, p[0], p[1], p[2]);
      worst = std::max({worst, std::abs(e.alpha - l.alpha), std::abs(e.color.r - l.color.r), std::abs(e.color.g - l.color.g),
                        std::abs(e.color.b - l.color.b)});
    }
    std::printf("pre-integration %u^3: max error %.3g over %zu random segments\n", size, worst, points.size());
    // Trilinear interpolation is second order where the integral is smooth; kinks along the
    // transfer function's breakpoints make some cells first order. Doubling the size must at
    // least halve the worst error.
    if (previous > 0.0) {
      EXPECT_LT(worst, 0.6 * previous) << size;
    }
    previous = worst;
  }
}

TEST(TransferFunction, BreakpointsMergeColourAndOpacity) {
  TransferFunction tf;
  tf.name = "t";
  tf.color = {{0.0, {0, 0, 0}}, {0.5, {1, 0, 0}}, {1.0, {1, 1, 1}}};
  tf.opacity = {{0.25, 0.2}, {0.75, 1.0}};
  tf.density_scale = 2.0;
  const auto b = breakpoints(tf);
  ASSERT_EQ(b.size(), 5u);  // 0, 0.25, 0.5, 0.75, 1
  EXPECT_DOUBLE_EQ(b[1].rgb.r, 0.5);
  EXPECT_DOUBLE_EQ(b[0].sigma, 0.4);   // opacity clamps to its first point
  EXPECT_DOUBLE_EQ(b[2].sigma, 1.2);   // halfway between 0.2 and 1.0, times 2
  EXPECT_DOUBLE_EQ(evaluate(b, 2.0).sigma, 2.0);  // beyond the range: clamped
}

TEST(TransferFunction, BadFunctionsAreRejected) {
  TransferFunction tf = preset("grayscale");
  tf.range_lo = tf.range_hi = 3.0;
  EXPECT_THROW(validate(tf), InputError);
  tf = preset("grayscale");
  tf.opacity = {{0.5, 0.1}, {0.2, 0.3}};
  EXPECT_THROW(validate(tf), InputError);
  tf = preset("grayscale");
  tf.color[0].rgb.g = 1.5;
  EXPECT_THROW(validate(tf), InputError);
  EXPECT_THROW(preset("no-such-map"), InputError);
  for (const auto& name : preset_names()) EXPECT_NO_THROW(validate(preset(name))) << name;
}

}  // namespace
}  // namespace prismoid::volume
