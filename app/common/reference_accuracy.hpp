#pragma once
// `render --reference-error`: how far a frame is from its CPU reference, measured, printed and
// written to the stats the same way for every scene a verb renders (volumes, mixed scenes).
#include <ostream>
#include <string>

#include "app/common/stats_json.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/metrics/image_error.hpp"

namespace prismoid::app {

struct ReferenceAccuracy {
  reference::ImageError error;  // of the display RGB for colour, else of the quantity
  double flip = 0.0;            // colour only: mean FLIP of the display
  double reference_ms = 0.0;    // the reference's CPU time
};

// `test` against `ref` (frame::frame_error; FLIP for colour).
ReferenceAccuracy measure_accuracy(const frame::OffscreenFrame& test, const frame::OffscreenFrame& ref, volume::Quantity quantity,
                                   double reference_ms);
// "  against the CPU reference (WHAT; N ms CPU): RMSE ..., largest difference ...[, FLIP ...]".
void print_accuracy(std::ostream& out, const ReferenceAccuracy& a, bool color, const std::string& what);
// Sets "reference_error" (rmse, max_abs, non_finite, reference_cpu_ms, and flip for colour).
void add_accuracy(StatsJson& stats, const ReferenceAccuracy& a, bool color);

}  // namespace prismoid::app
