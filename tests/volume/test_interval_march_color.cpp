// Marched colour (Tricard 2024, section 3.2, with emission-absorption through a transfer
// function): the GPU's march against the CPU reference `field_color_image`, composited in
// exact visibility order. Each test states where its tolerance comes from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/analytic_march.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/tet_mesh.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"
#include "volume/step_convergence.hpp"

namespace prismoid {
namespace {

constexpr double kUlp = 0x1p-24;  // float's unit roundoff

Camera looking_from(const glm::dvec3& eye) {
  Camera c;
  c.eye = eye;
  c.target = glm::dvec3(0.0);
  c.up = glm::dvec3(0, 1, 0);
  c.fovy_degrees = 40.0;
  c.near_distance = 0.05;
  return c;
}

// Colour and opacity linear over the field's whole range: the extinction and colour along a
// ray are then smooth functions of the field (no breakpoint kinks), so the midpoint rule's
// error is bounded by the field's derivatives alone (see ColorStepBound).
volume::TransferFunction linear_tf(double density) {
  volume::TransferFunction tf;
  tf.name = "linear ramp";
  tf.color = {{0.0, {0.1, 0.2, 0.9}}, {1.0, {0.9, 0.6, 0.1}}};
  tf.opacity = {{0.0, 0.1}, {1.0, 1.0}};
  tf.range_lo = 0.0;  // Marschner-Lobb's values lie in [0, 1]: no clamping either
  tf.range_hi = 1.0;
  tf.density_scale = density;
  return tf;
}

// |grad f| over all points: Marschner-Lobb's radial derivative is at most alpha pi^2 f_M /
// (2 (1 + alpha)) and its z derivative pi / (4 (1 + alpha)) (analytic_field.cpp).
double gradient_bound(const volume::AnalyticField& field) {
  const double f_m = field.params[0].x, alpha = field.params[0].y;
  return (alpha * M_PI * M_PI * f_m + M_PI / 2.0) / (2.0 * (1.0 + alpha));
}

// The midpoint march's error for the composited colour over a ray of length L inside the
// mesh, steps h <= S, for a transfer function linear in the field (slopes of extinction
// D op_s / R and of colour c_s / R per unit field, R the range's width). Along the unit-speed
// ray sigma' <= s1 = D op_s |grad f| / R, sigma'' <= s2 = D op_s B / R (B the field's second
// derivative bound), likewise c' <= c1, c'' <= c2 with c_s, and the emission G = c sigma
// (c = 1 for alpha) has G' <= g1 = c1 sigma_max + s1, G'' <= g2 = c2 sigma_max + 2 c1 s1 + s2.
// The march is exactly the emission-absorption of the piecewise-constant (midpoint) G_h and
// sigma_h, int G_h e^-tau_h. Against int G e^-tau:
//  - int (G - G_h) e^-tau, per step: e^-tau(m) times the midpoint error of G (<= h^3 g2 / 24),
//    plus int |G - G_h| |e^-tau - e^-tau(m)| <= g1 sigma_max h^3 / 12; summed, L S^2 (g2 / 24
//    + g1 sigma_max / 12);
//  - int G_h (e^-tau - e^-tau_h) <= (e^dtau - 1) int sigma_h e^-tau_h <= e^dtau - 1, as
//    colours are at most 1; dtau = max |tau - tau_h| <= L S^2 s2 / 24 (whole steps) + S^2 s1 / 8
//    (within one).
struct ColorStepBound {
  double s1, s2, g1, g2, sigma_max;
  double sigma_per_field, colour_per_field;  // D op_s / R and c_s / R
  double operator()(double length, double step) const {
    const double dtau = length * step * step * s2 / 24.0 + step * step * s1 / 8.0;
    return length * step * step * (g2 / 24.0 + g1 * sigma_max / 12.0) + std::expm1(dtau);
  }
};

ColorStepBound color_step_bound(const volume::AnalyticField& field, const volume::TransferFunction& tf) {
  const double range = tf.range_hi - tf.range_lo;
  const double op_slope = std::abs(tf.opacity[1].opacity - tf.opacity[0].opacity) / (tf.opacity[1].x - tf.opacity[0].x);
  const glm::dvec3 dc = glm::abs(tf.color[1].rgb - tf.color[0].rgb) / (tf.color[1].x - tf.color[0].x);
  const double c_slope = std::max({dc.x, dc.y, dc.z});
  const double grad = gradient_bound(field), second = volume::second_derivative_bound(field);
  ColorStepBound b;
  b.sigma_max = tf.density_scale * std::max(tf.opacity[0].opacity, tf.opacity[1].opacity);
  b.sigma_per_field = tf.density_scale * op_slope / range;
  b.colour_per_field = c_slope / range;
  b.s1 = b.sigma_per_field * grad;
  b.s2 = b.sigma_per_field * second;
  const double c1 = b.colour_per_field * grad, c2 = b.colour_per_field * second;
  b.g1 = c1 * b.sigma_max + b.s1;
  b.g2 = c2 * b.sigma_max + 2.0 * c1 * b.s1 + b.s2;
  return b;
}

struct ColorComparison {
  size_t covered = 0, failures = 0;
  double rmse = 0.0, max_error = 0.0, worst_over_tolerance = 0.0;
  std::string first_failure, ordering;
  bool order_exact = false;
};

// On both interval backends (the compute backend orders each pixel itself: `ordering` is the
// mesh backend's).
class IntervalMarchColorTest : public test::GpuTest, public test::OnBackend {
 public:
  frame::OffscreenFrame render(const TetMesh& mesh, const volume::AnalyticField& field, const volume::TransferFunction& tf,
                               double step, const Camera& camera, uint32_t w, uint32_t h, frame::Ordering ordering) {
    frame::FrameRenderer renderer(device(), mesh);
    frame::FrameSettings settings = settings_on_backend();
    settings.resolve.quantity = volume::Quantity::Color;
    settings.resolve.transfer = tf;
    settings.resolve.march.enabled = true;
    settings.resolve.march.field = field;
    settings.resolve.march.step = step;
    settings.ordering = ordering;
    return renderer.render_offscreen(camera, settings, {w, h});
  }

  // The GPU's march at `step` against the reference at `ref_step`, per pixel and channel,
  // within: both marches' step bounds (ColorStepBound over the ray's length inside);
  // rasterizer snapping, as in test_emission_absorption.cpp: the largest change of the
  // reference when the ray moves by 2 * 2^-subPixelPrecisionBits pixel (the march samples the
  // exact pixel ray but its interval's ends come from snapped proxies); and float:
  //  - each of the n <= L / S + segments steps: 1 - exp(-sigma h) and the blend, 8 roundings of
  //    numbers at most 1;
  //  - the sample's position carries 2^-20 of max(|eye|, distance) (8 roundings, doubled), the
  //    field's float evaluation 2^-21 k beta (its cosine's argument, up to k = 2 pi f_M,
  //    rounded a few times, times beta = alpha / (2 (1 + alpha))) plus 16 ulp; a field error
  //    df moves the colour by at most L (c_s sigma_max + D op_s) / R df;
  //  - each segment's length: 2^-18 of its far end's distance (two reciprocals of
  //    interpolated 1/depth, as for optical depth), times sigma_max, plus its blend's rounding.
  ColorComparison compare(const TetMesh& mesh, const volume::AnalyticField& field, const volume::TransferFunction& tf,
                          double step, double ref_step, const Camera& camera, uint32_t w, uint32_t h, frame::Ordering ordering) {
    const frame::OffscreenFrame gpu = render(mesh, field, tf, step, camera, w, h, ordering);
    const reference::ColorImage ref = reference::field_color_image(mesh, field, tf, camera, w, h, ref_step);
    const double radius = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
    std::vector<double> snap(size_t(w) * h, 0.0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy) continue;
        const auto moved = reference::field_color_image(mesh, field, tf, camera, w, h, ref_step, dx * radius, dy * radius);
        for (size_t i = 0; i < snap.size(); ++i)
          for (int c = 0; c < 4; ++c) snap[i] = std::max(snap[i], std::abs(moved.pixels[i][c] - ref.pixels[i][c]));
      }
    std::vector<double> length(snap.size(), 0.0);
    reference::trace_cells(mesh, camera, w, h, 0.0, 0.0, [](size_t) { return true; },
                           [&](size_t p, size_t, const reference::Interval& in, const glm::dvec3&) { length[p] += in.exit - in.enter; });
    const ColorStepBound bound = color_step_bound(field, tf);
    const double f_m = field.params[0].x, alpha = field.params[0].y;
    const double reach = glm::length(camera.eye) + 2.0 * std::sqrt(3.0);
    const double field_error = gradient_bound(field) * 0x1p-20 * reach + 0x1p-21 * 2.0 * M_PI * f_m * alpha / (2.0 * (1.0 + alpha)) +
                               16.0 * kUlp;
    const double colour_per_field = bound.colour_per_field * bound.sigma_max + bound.sigma_per_field;

    ColorComparison c;
    c.ordering = gpu.report.ordering;
    c.order_exact = gpu.report.order_exact;
    for (size_t i = 0; i < snap.size(); ++i) {
      const double segments = ref.segments[i], n = std::ceil(length[i] / step) + segments;
      const double float_tol = n * 8.0 * kUlp + length[i] * colour_per_field * field_error +
                               segments * (bound.sigma_max * 0x1p-18 * reach + kUlp);
      const double tol = bound(length[i], step) + bound(length[i], ref_step) + snap[i] + float_tol;
      if (ref.pixels[i].a > 0.0) ++c.covered;
      for (int ch = 0; ch < 4; ++ch) {
        const double err = std::abs(double(gpu.emission[4 * i + ch]) - ref.pixels[i][ch]);
        c.rmse += err * err;
        c.max_error = std::max(c.max_error, err);
        c.worst_over_tolerance = std::max(c.worst_over_tolerance, err / tol);
        if (err > tol && c.failures++ == 0)
          c.first_failure = "pixel (" + std::to_string(i % w) + "," + std::to_string(i / w) + ") channel " + std::to_string(ch) +
                            ": gpu " + std::to_string(gpu.emission[4 * i + ch]) + " reference " +
                            std::to_string(ref.pixels[i][ch]) + " tolerance " + std::to_string(tol);
      }
    }
    c.rmse = std::sqrt(c.rmse / (4.0 * double(snap.size())));
    return c;
  }
};

// Marschner-Lobb in a 4^3 Kuhn box (convex, acyclic: the exact order is exact for every ray),
// optical depths of several units, so the order matters; the tolerance must also tell a
// wrong order from the right one.
TEST_P(IntervalMarchColorTest, MarschnerLobbColourMatchesReferenceInExactOrder) {
  const volume::AnalyticField field = volume::marschner_lobb();
  const TetMesh mesh = volume::make_field_mesh(field, 4);
  const volume::TransferFunction tf = linear_tf(4.0);
  const Camera camera = looking_from({-0.9, 0.7, -3.6});
  const auto exact = compare(mesh, field, tf, 0.0025, 1e-3, camera, 40, 40, frame::Ordering::Exact);
  EXPECT_TRUE(exact.order_exact) << exact.ordering;
  EXPECT_GT(exact.covered, 300u);
  EXPECT_EQ(exact.failures, 0u) << exact.first_failure;
  std::printf("exact order: max error %.3g, rmse %.3g, worst pixel at %.3f of its tolerance\n", exact.max_error, exact.rmse,
              exact.worst_over_tolerance);
  if (compute()) return;  // the compute backend has no mesh order or GPU sort; the tolerance's power is the same
  const auto unsorted = compare(mesh, field, tf, 0.0025, 1e-3, camera, 40, 40, frame::Ordering::MeshOrder);
  std::printf("mesh order: max error %.3g, rmse %.3g, %zu pixel channels beyond tolerance\n", unsorted.max_error, unsorted.rmse,
              unsorted.failures);
  EXPECT_GT(unsorted.failures, 0u) << "the tolerance cannot tell a wrong order from the right one";
  const auto sorted = compare(mesh, field, tf, 0.0025, 1e-3, camera, 40, 40, frame::Ordering::GpuSort);
  std::printf("gpu sort: max error %.3g, rmse %.3g\n", sorted.max_error, sorted.rmse);
  EXPECT_LT(sorted.rmse, 0.5 * unsorted.rmse);
}

// With a transfer function of many breakpoints (viridis, an opacity ramp with kinks) the
// extinction along a ray has a kink wherever the field crosses a breakpoint: a step holding a
// kink of slope jump J errs by at most J h^2 / 8 instead of h^3 / 24 |G''|, still second order
// overall. The rasterization is identical at every step (snapping cancels), so consecutive
// differences shrink about 4x per halving: steps are ceil(len / S) per cell, a halving shrinks
// a cell's step 1.5x to 2x (ratio 2.25 to 4), more when the coarser count was rounded up, hence
// [2.5, 6] as for optical depth (test_interval_march.cpp). The finest step stays well above
// float's floor (n * 8 ulp, n ~ 1400 steps: 7e-4 at worst, far less in practice), which a
// finer step would reach.
TEST_P(IntervalMarchColorTest, MarschnerLobbColourConvergesSecondOrderThroughBreakpoints) {
  const volume::AnalyticField field = volume::marschner_lobb();
  const TetMesh mesh = volume::make_field_mesh(field, 4);
  volume::TransferFunction tf = volume::preset("viridis");
  tf.opacity = {{0.0, 0.0}, {0.2, 0.3}, {0.6, 0.8}, {1.0, 1.0}};
  tf.density_scale = 4.0;
  const Camera camera = looking_from({0.9, 0.7, 3.6});
  const std::vector<double> steps = {0.02, 0.01, 0.005, 0.0025};
  std::vector<std::vector<float>> images;
  for (double s : steps) images.push_back(render(mesh, field, tf, s, camera, 40, 40, frame::Ordering::Exact).emission);
  test::expect_second_order_in_step(steps, images);
}

PRISMOID_ON_BOTH_BACKENDS(IntervalMarchColorTest);

}  // namespace
}  // namespace prismoid
