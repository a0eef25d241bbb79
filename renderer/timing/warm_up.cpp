#include "renderer/timing/warm_up.hpp"

#include <chrono>
#include <cmath>
#include <vector>

#include "renderer/timing/frame_timing.hpp"

namespace prismoid::timing {

uint32_t warm_up(const std::function<double()>& frame, double seconds) {
  // The clock sampler starts now, so its samples come while these frames keep the GPU busy: timed
  // frames shorter than its period then carry the clock they started at, not the idle one after.
  process_sm_clock();
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> ms;
  auto median4 = [&](size_t end) { return median_of({ms.begin() + long(end) - 4, ms.begin() + long(end)}); };
  for (;;) {
    ms.push_back(frame());
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed < seconds) continue;
    if (elapsed >= 4.0 * seconds || !std::isfinite(ms.back())) break;  // no timestamps: nothing to watch
    if (ms.size() >= 8 && median4(ms.size()) >= 0.98 * median4(ms.size() - 4)) break;
  }
  return uint32_t(ms.size());
}

}  // namespace prismoid::timing
