// Marching inside intervals (Tricard 2024, section 3.2): the fragment samples an analytic
// field along its interval. Each test states where its tolerance comes from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <map>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/analytic_march.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/tet_mesh.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"
#include "support/march_fixture.hpp"
#include "volume/step_convergence.hpp"

namespace prismoid {
namespace {

using test::kUlp;
using test::looking_from;
using IntervalMarchTest = test::MarchTest;

// (a) A linear field: the midpoint rule is exact, so the march must give what interval
// shading gives with the same field as exact per-point extinction, through the same proxies
// (same rasterization; what snapping leaves is MarchTest::snapped_field_tolerance, on the mesh
// backend only). What remains is float arithmetic: the march sums
// n samples (n <= ceil(longest edge / step)) of a field computed from a world position that
// carries ~8 roundings of max(|eye|, distance) (2^-21 relative) and a dot product (4 roundings
// of |g||p| + |c|); the sum adds n roundings of the running total; interval shading's own
// mean * length adds a few ulp. Bound per pixel: tau * (n + 16) * 2^-23 plus, over the ray's
// length L, density * |g| * 2^-21 * max(|eye|, distance) * L.
TEST_P(IntervalMarchTest, LinearFieldMarchEqualsExactIntervalShading) {
  const volume::AnalyticField field = volume::field_from_name("linear");
  const TetMesh mesh = volume::make_field_mesh(field, 4);
  for (const glm::dvec3 eye : {glm::dvec3(0.4, 0.3, 4.5), glm::dvec3(-3.0, 2.0, -2.5), glm::dvec3(0.2, 0.1, 0.3)}) {
    Camera camera = looking_from(eye, glm::dvec3(0.0), eye.z < 1.0 ? 80.0 : 40.0);
    if (eye.z < 1.0) camera.target = glm::dvec3(0.5, -0.3, -1.0);
    const double step = 0.05;
    const auto march = render(mesh, field, volume::Quantity::OpticalDepth, step, camera, 40, 40);
    const auto exact = render_exact_optical_depth(mesh, camera, 40, 40);
    const double longest = std::sqrt(3.0) * 2.0 / 4.0;  // a Kuhn cube's diagonal (n = 4 over [-1, 1])
    const double n = std::ceil(longest / step);
    const double g = glm::length(glm::dvec3(field.params[0]));
    const double reach = glm::length(eye) + 2.0 * std::sqrt(3.0);  // |eye| or farthest distance
    size_t covered = 0;
    double worst = 0.0;
    for (size_t i = 0; i < exact.quantity.size(); ++i) {
      const double tau = exact.quantity[i];
      if (tau > 0.0) ++covered;
      const double tol = tau * (n + 16.0) * 2.0 * kUlp + g * 8.0 * kUlp * reach * 2.0 * std::sqrt(3.0) +
                         snapped_field_tolerance(camera, 40, g, reach, 2.0 * std::sqrt(3.0));
      const double err = std::abs(double(march.quantity[i]) - tau);
      worst = std::max(worst, err / tol);
      EXPECT_LE(err, tol) << "pixel " << i << " eye " << eye.x << "," << eye.y << "," << eye.z << ": march " << march.quantity[i]
                          << " exact " << tau;
    }
    EXPECT_GT(covered, 200u);
    std::printf("linear field: worst pixel at %.3f of its tolerance\n", worst);
  }
}

// Per pixel, over the cells the ray crosses, how much the cell's optical depth changes when
// its interval's ends move as the rasterizer's snapping moves them: the fragment samples the
// exact pixel ray (gl_FragCoord), but its front and back depths come from proxies whose
// vertices snap (see tests/volume/interval_comparison.cpp), i.e. they are the depths of the
// cell's faces at a point within `radius` pixels. The change is at most sigma at each end
// times how far that end moves, sampled at 8 neighbours (the factor 4 in `radius` is the
// margin for sampling), plus a float ulp of slack; summed over cells (they move independently).
std::vector<double> snapping_tolerance(const TetMesh& mesh, const volume::AnalyticField& field, const Camera& camera, uint32_t w,
                                       uint32_t h, double radius) {
  auto per_cell = [&](double ox, double oy) {
    std::vector<std::map<size_t, reference::Interval>> cells(size_t(w) * h);
    reference::trace_cells(mesh, camera, w, h, ox, oy, [](size_t) { return true; },
                           [&](size_t pixel, size_t cell, const reference::Interval& in, const glm::dvec3&) {
                             // as depths along the viewing axis: comparable between neighbouring rays
                             const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
                             const double to_depth = glm::dot(reference::ray_direction(camera, w, h, double(pixel % w) + 0.5 + ox,
                                                                                       double(pixel / w) + 0.5 + oy), forward);
                             cells[pixel][cell] = {in.enter * to_depth, in.exit * to_depth};
                           });
    return cells;
  };
  const auto centre = per_cell(0.0, 0.0);
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  std::vector<std::map<size_t, double>> largest(centre.size());
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (!dx && !dy) continue;
      const auto moved = per_cell(dx * radius, dy * radius);
      for (size_t p = 0; p < centre.size(); ++p) {
        const glm::dvec3 dir = reference::ray_direction(camera, w, h, double(p % w) + 0.5, double(p / w) + 0.5);
        const double length_per_depth = 1.0 / glm::dot(dir, forward);
        auto sigma_at_depth = [&](double d) { return std::max(volume::evaluate(field, camera.eye + d * length_per_depth * dir), 0.0); };
        std::map<size_t, reference::Interval> all = centre[p];
        for (const auto& [c, in] : moved[p]) all.emplace(c, reference::Interval{in.enter, in.enter});
        for (const auto& [c, in] : all) {
          const reference::Interval a = centre[p].count(c) ? centre[p].at(c) : reference::Interval{in.enter, in.enter};
          const reference::Interval b = moved[p].count(c) ? moved[p].at(c) : reference::Interval{a.enter, a.enter};
          const double change = (std::max(sigma_at_depth(a.enter), sigma_at_depth(b.enter)) * std::abs(a.enter - b.enter) +
                                 std::max(sigma_at_depth(a.exit), sigma_at_depth(b.exit)) * std::abs(a.exit - b.exit)) *
                                length_per_depth;
          largest[p][c] = std::max(largest[p][c], change);
        }
      }
    }
  std::vector<double> tol(centre.size(), 0.0);
  for (size_t p = 0; p < tol.size(); ++p)
    for (const auto& [c, v] : largest[p]) tol[p] += v;
  return tol;
}

// (b) Marschner-Lobb (f_M = 6, alpha = 0.25) in cells of a 4^3 Kuhn box: strongly non-linear
// per cell. The midpoint rule's error on a segment of length L with steps h <= S is at most
// L S^2 / 24 * max|f''| (volume::second_derivative_bound), so the error is second order:
//  - differences of consecutive GPU images (S, S/2) shrink about 4x per halving: the
//    rasterization is identical in both, so snapping cancels; steps are ceil(len / S) per
//    cell, so a halving shrinks a cell's step by 1.5x to 2x (ratio 2.25..4 per cell; more
//    when the step count of the coarser image was already rounded up), hence [2.5, 6];
//  - at the finest step, the error against the accurate reference (Gauss-Legendre, panel
//    0.005) is within the step bound, plus snapping (per cell, radius 2 * 2^-subpixel bits)
//    plus float: n samples summed, 2^-21 relative position error times |grad f| (<= pi^2 f_M
//    alpha pi / 2 / (2 (1 + alpha)) + pi / 4 / (2 (1 + alpha)) bounded by second_derivative
//    bound * 2 on [-1,1]^3) times the ray's length.
TEST_P(IntervalMarchTest, MarschnerLobbOpticalDepthConvergesSecondOrder) {
  const volume::AnalyticField field = volume::marschner_lobb();
  const TetMesh mesh = volume::make_field_mesh(field, 4);
  const Camera camera = looking_from({0.9, 0.7, 3.6});
  const uint32_t w = 40, h = 40;
  const std::vector<double> steps = {0.02, 0.01, 0.005, 0.0025};
  std::vector<std::vector<float>> images;
  for (double s : steps) images.push_back(render(mesh, field, volume::Quantity::OpticalDepth, s, camera, w, h).quantity);
  test::expect_second_order_in_step(steps, images);
  const std::vector<double> ref = reference::field_optical_depth_image(mesh, field, 1.0, camera, w, h);
  const double radius = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
  const std::vector<double> snap = snapping_tolerance(mesh, field, camera, w, h, radius);
  const double fine = steps.back(), diagonal = 2.0 * std::sqrt(3.0);
  const double step_bound = diagonal * fine * fine / 24.0 * volume::second_derivative_bound(field);
  const double reach = glm::length(camera.eye) + diagonal;
  // |grad f| <= (alpha pi^2 f_M + pi / 2) / (2 (1 + alpha)): the radial derivative's factors
  // |sin| <= 1 and |sin(pi r / 2)| <= 1, and the z derivative pi / 2 |cos| (analytic_field.cpp).
  const double f_m = field.params[0].x, alpha = field.params[0].y;
  const double grad_bound = (alpha * M_PI * M_PI * f_m + M_PI / 2.0) / (2.0 * (1.0 + alpha));
  double max_err = 0.0, worst = 0.0;
  std::vector<double> tolerances;
  for (size_t i = 0; i < ref.size(); ++i) {
    const double n = std::ceil(diagonal / fine);
    const double float_tol = ref[i] * (n + 16.0) * 2.0 * kUlp + grad_bound * 8.0 * kUlp * reach * diagonal;
    const double tol = step_bound + snap[i] + float_tol;
    if (ref[i] > 0.0) tolerances.push_back(tol);
    const double err = std::abs(double(images.back()[i]) - ref[i]);
    max_err = std::max(max_err, err);
    worst = std::max(worst, err / tol);
    EXPECT_LE(err, tol) << "pixel " << i << ": gpu " << images.back()[i] << " reference " << ref[i];
  }
  std::sort(tolerances.begin(), tolerances.end());
  ASSERT_GT(tolerances.size(), 300u);
  std::printf("finest step %.4f: max error %.3g (step bound %.3g, median tolerance %.3g), worst pixel at %.3f of its tolerance\n",
              fine, max_err, step_bound, tolerances[tolerances.size() / 2], worst);
}

// (c) One Gaussian blob of width w: its isosurface at V is exactly the sphere of radius
// w sqrt(2 ln(1/V)) round its centre. Coverage must be exactly the disc, except silhouette
// pixels: rays whose chord through the sphere is shorter than two steps (the march can step
// over it) or that pass within 1e-4 of tangency (float). Depth: bisection stops one float
// apart in depth (2^-23 relative); the field's float value strays by at most 16 ulp of 1
// (exp and sums) and the sample's position by 2^-20 of max(|eye|, distance) (8 roundings,
// doubled), which move the hit by dF / (|grad f| cos) and dP / cos along the ray, cos the
// angle between the ray and the normal. Shade: ambient + (1 - ambient) |cos|, off by the
// normal's float error (2^-18) and the hit's position error over the radius.
TEST_P(IntervalMarchTest, SphereIsosurfaceHitsAtTheExactDepth) {
  const volume::AnalyticField field = volume::field_from_name("sphere");
  const glm::dvec3 centre(field.params[0]);
  const double width = field.params[0].w, iso = 0.5;
  const double radius = width * std::sqrt(2.0 * std::log(1.0 / iso));
  const double grad_at_surface = iso * radius / (width * width);
  const TetMesh mesh = volume::make_field_mesh(field, 4);
  const double step = 0.02;
  const uint32_t w = 48, h = 48;
  for (const glm::dvec3 eye : {glm::dvec3(0.3, 0.2, 2.4), glm::dvec3(-1.7, 1.1, -1.4)}) {
    const Camera camera = looking_from(eye);
    const auto gpu = render(mesh, field, volume::Quantity::Isosurface, step, camera, w, h, iso);
    const auto cpu = reference::isosurface_image(mesh, field, iso, camera, w, h, 1e-3);
    size_t disc = 0, silhouette = 0;
    double worst = 0.0;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const glm::dvec3 dir = reference::ray_direction(camera, w, h, x + 0.5, y + 0.5);
        const double along = glm::dot(centre - eye, dir);
        const double b2 = glm::dot(centre - eye, centre - eye) - along * along;  // squared closest approach
        const double half_chord = b2 < radius * radius ? std::sqrt(radius * radius - b2) : 0.0;
        const bool near_silhouette = (half_chord > 0.0 && half_chord < step) || std::abs(std::sqrt(b2) - radius) < 1e-4;
        const float distance = gpu.emission[4 * i + 3], shade = gpu.emission[4 * i];
        if (near_silhouette) { ++silhouette; continue; }
        const bool hit = half_chord > 0.0;
        EXPECT_EQ(distance > 0.0f, hit) << "pixel (" << x << "," << y << ")";
        EXPECT_EQ(cpu.distance[i] > 0.0, hit) << "reference, pixel (" << x << "," << y << ")";
        if (!hit || !(distance > 0.0f)) continue;
        ++disc;
        const double exact = along - half_chord;
        const double cos_angle = half_chord / radius;
        const double reach = std::max(glm::length(eye), exact);
        const double tol = 2.0 * std::ldexp(1.0, -23) * exact + 16.0 * kUlp / (grad_at_surface * cos_angle) +
                           std::ldexp(1.0, -20) * reach / cos_angle;
        worst = std::max(worst, std::abs(double(distance) - exact) / tol);
        EXPECT_NEAR(distance, exact, tol) << "pixel (" << x << "," << y << ")";
        EXPECT_NEAR(cpu.distance[i], exact, 1e-9) << "reference, pixel (" << x << "," << y << ")";
        const double exact_shade = PRISMOID_ISOSURFACE_AMBIENT + (1.0 - PRISMOID_ISOSURFACE_AMBIENT) * cos_angle;
        EXPECT_NEAR(shade, exact_shade, std::ldexp(1.0, -18) + 2.0 * tol / radius) << "pixel (" << x << "," << y << ")";
      }
    EXPECT_GT(disc, 100u);
    std::printf("sphere isosurface: %zu disc pixels, %zu silhouette pixels skipped, worst depth at %.3f of its tolerance\n",
                disc, silhouette, worst);
  }
}

PRISMOID_ON_BOTH_BACKENDS(IntervalMarchTest);

}  // namespace
}  // namespace prismoid
