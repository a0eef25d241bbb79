// Tolerance per pixel and channel of a colour frame against the reference.
//
// The GPU integrates each segment exactly (piece by piece of the transfer function, in float)
// or looks it up in the pre-integration table. The table's own error against the exact
// integral is a quality setting, tested on the CPU (test_segment_integral.cpp) and measured by
// the bench; with a table, the reference here looks segments up in the same table. Either way
// the tolerance covers only what the GPU adds, per pixel and channel:
//  1. rasterizer snapping, as for optical depth (see test_interval_shading.cpp): the largest
//     change of the reference when the pixel's ray moves by 2 * 2^-subPixelPrecisionBits;
//  2. float32 inputs of each segment: the normalized scalar x at both ends and the segment's
//     length come from values relative to the cell's reference point, as for optical depth
//     (interval_comparison.cpp derives the budget): each end's depth moves by 2^-19 of the
//     cell's depth extent times its depth ratio (more for cells the near plane cuts), plus 2^-19
//     of (x + y + 1) pixels times the surface's screen gradient (plane equations in window
//     coordinates); x by 2^-20 (its own mapping into [0, 1]) plus 2^-19 of the cell's spread of
//     x times the depth ratio plus the same window term. The reference sums, over the pixel's
//     segments, how much each segment changes when its inputs move that far (finite differences
//     of the same integral);
//  3. the blend: one rounding (2^-24 relative) per segment composited, and the table's float
//     texels (2^-24 relative), per segment; for exact integration in float, 2^-18 per piece
//     of the transfer function (the Gauss-Legendre sums and the cancelling terms of the
//     closed form lose a few ulp each), at most one piece per transfer-function sample.
// The compute backend, which finds each interval on the pixel's own ray (no snapping, no window
// coordinates), is held to the same tolerances.
#include "volume/color_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "renderer/reference/emission_absorption.hpp"

namespace prismoid::test {

ColorReference color_reference(uint32_t subpixel_bits, const TetMesh& mesh, const volume::TransferFunction& tf, const Camera& camera,
                               uint32_t w, uint32_t h, const volume::PreintegrationTable* table, const std::vector<float>* depth_limit) {
  reference::InputPerturbation perturbation;
  const double s = 2.0 * std::ldexp(1.0, -int(subpixel_bits));
  perturbation.x_absolute = std::ldexp(1.0, -20);
  perturbation.relative = std::ldexp(1.0, -19);
  perturbation.window = std::ldexp(1.0, -19);
  perturbation.step = 0.25 * s;
  ColorReference r;
  r.image = reference::emission_absorption_image(mesh, tf, camera, w, h, 0.0, 0.0, table, &perturbation, depth_limit);
  const auto& ref = r.image;
  std::vector<double> snap_tol(size_t(w) * h, 0.0);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (!dx && !dy) continue;
      const auto shifted = reference::emission_absorption_image(mesh, tf, camera, w, h, dx * s, dy * s, table, nullptr, depth_limit);
      for (size_t i = 0; i < snap_tol.size(); ++i)
        for (int c = 0; c < 4; ++c) snap_tol[i] = std::max(snap_tol[i], std::abs(shifted.pixels[i][c] - ref.pixels[i][c]));
    }
  const auto samples = volume::breakpoints(tf);
  const double integral_tol = table ? std::ldexp(1.0, -24) : std::ldexp(1.0, -18) * double(samples.size());
  r.tolerance.resize(snap_tol.size());
  for (size_t i = 0; i < snap_tol.size(); ++i) {
    const double n = ref.segments[i] + 1.0;
    r.tolerance[i] = snap_tol[i] + ref.sensitivity[i] + n * (integral_tol + std::ldexp(1.0, -24));
  }
  return r;
}

ColorComparison ColorTest::compare(const TetMesh& mesh, const volume::TransferFunction& tf, const Camera& camera, uint32_t w,
                                   uint32_t h, frame::Ordering ordering, uint32_t table_size,
                                   std::optional<frame::IntervalBackend> backend, std::shared_ptr<const std::vector<float>> depth_limit) {
  frame::FrameRenderer renderer(device(), mesh);
  frame::FrameSettings settings = settings_on_backend();
  if (backend) settings.backend = *backend;
  settings.resolve.quantity = volume::Quantity::Color;
  settings.resolve.transfer = tf;
  settings.resolve.preintegration_size = table_size;
  settings.ordering = ordering;
  settings.resolve.depth_limit = depth_limit;
  const frame::OffscreenFrame gpu = renderer.render_offscreen(camera, settings, {w, h});
  // The table the GPU used, its length axis back in world units (the GPU draws in the data's
  // units, frame/frame_units.hpp; its texels hold dimensionless sigma * length).
  std::optional<volume::PreintegrationTable> world_table;
  if (table_size > 0) {
    world_table = renderer.volume_inputs().table();
    world_table->max_length *= renderer.units().unit;
  }
  const volume::PreintegrationTable* table = world_table ? &*world_table : nullptr;
  const ColorReference reference =
      color_reference(device().capabilities().subpixel_precision_bits, mesh, tf, camera, w, h, table, depth_limit.get());
  const auto& ref = reference.image;

  ColorComparison c;
  for (const auto& p : gpu.passes) c.passes.push_back(p.name);
  c.ordering = gpu.report.ordering;
  c.order_exact = gpu.report.order_exact;
  c.report = gpu.report;
  const size_t pixels = size_t(w) * h;
  c.colour_failed.assign(pixels, false);
  c.alpha_failed.assign(pixels, false);
  c.segments = ref.segments;
  for (size_t i = 0; i < pixels; ++i) {
    const double tol = reference.tolerance[i];
    if (ref.pixels[i].a > 0.0) ++c.covered;
    for (int ch = 0; ch < 4; ++ch) {
      const float g = gpu.emission[4 * i + ch];
      EXPECT_TRUE(std::isfinite(g)) << "pixel " << i << " channel " << ch;
      const double err = std::abs(double(g) - ref.pixels[i][ch]);
      c.rmse += err * err;
      c.max_error = std::max(c.max_error, err);
      c.worst_over_tolerance = std::max(c.worst_over_tolerance, err / tol);
      if (err > tol) (ch == 3 ? c.alpha_failed : c.colour_failed)[i] = true;
      if (err > tol && c.failures++ == 0)
        c.first_failure = "pixel (" + std::to_string(i % w) + "," + std::to_string(i / w) + ") channel " + std::to_string(ch) +
                          ": gpu " + std::to_string(g) + " reference " + std::to_string(ref.pixels[i][ch]) + " tolerance " +
                          std::to_string(tol) + " segments " + std::to_string(ref.segments[i]);
    }
  }
  c.rmse = std::sqrt(c.rmse / (4.0 * double(pixels)));
  return c;
}

}  // namespace prismoid::test
