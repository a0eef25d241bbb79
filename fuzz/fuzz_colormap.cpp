// ParaView colour-map JSON, then what a renderer does with the result (breakpoints, evaluation).
#include <cmath>
#include <limits>
#include <sstream>

#include "fuzz/fuzz_input.hpp"
#include "io/transfer_function_io.hpp"

using namespace prismoid;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  fuzz::expect_input_errors_only([&] {
    const volume::TransferFunction tf = io::parse_paraview_colormap(in, "fuzz.json");
    const std::vector<volume::TfSample> samples = volume::breakpoints(tf);
    fuzz::require(!samples.empty(), "a validated transfer function has breakpoints");
    for (double x : {-1.0, 0.0, 0.25, 0.5, 1.0, 2.0}) {
      const volume::TfSample s = volume::evaluate(samples, x);
      fuzz::require(std::isfinite(s.sigma) && s.sigma >= 0.0, "extinction is finite and not negative");
      // Interpolating between values in [0, 1] rounds three times (two products, one sum), each by
      // at most half an ulp of 1: the result stays within 2 eps of the interval.
      const double slack = 2.0 * std::numeric_limits<double>::epsilon();
      for (int c = 0; c < 3; ++c) fuzz::require(s.rgb[c] >= -slack && s.rgb[c] <= 1.0 + slack, "colour stays in [0, 1]");
    }
  });
  return 0;
}
