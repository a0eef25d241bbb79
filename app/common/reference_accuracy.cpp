#include "app/common/reference_accuracy.hpp"

#include "app/common/cli_args.hpp"
#include "renderer/volume/cpu/reference_frame.hpp"
#include "renderer/metrics/flip.hpp"

namespace prismoid::app {

ReferenceAccuracy measure_accuracy(const frame::OffscreenFrame& test, const frame::OffscreenFrame& ref, volume::Quantity quantity,
                                   double reference_ms) {
  ReferenceAccuracy a;
  a.reference_ms = reference_ms;
  a.error = frame::frame_error(test, ref, quantity);
  if (quantity == volume::Quantity::Color) a.flip = reference::flip(test.display, ref.display, test.width, test.height, 4).mean;
  return a;
}

void print_accuracy(std::ostream& out, const ReferenceAccuracy& a, bool color, const std::string& what) {
  out << "  against the CPU reference (" << what << "; " << json_number(a.reference_ms) << " ms CPU): RMSE " << json_number(a.error.rmse)
      << ", largest difference " << json_number(a.error.max_abs) << (color ? " (display RGB)" : "");
  if (color) out << ", FLIP " << json_number(a.flip);
  if (a.error.non_finite) out << "; " << a.error.non_finite << " values not finite";
  out << "\n";
}

void add_accuracy(StatsJson& stats, const ReferenceAccuracy& a, bool color) {
  stats["reference_error"] = {{"rmse", a.error.rmse}, {"max_abs", a.error.max_abs}, {"non_finite", a.error.non_finite},
                              {"reference_cpu_ms", a.reference_ms}};
  if (color) stats["reference_error"]["flip"] = a.flip;
}

}  // namespace prismoid::app
