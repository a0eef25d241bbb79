#include "app/common/warm_up.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <vector>

namespace prismoid::app {

uint32_t warm_up(const std::function<double()>& frame, double seconds) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<double> ms;
  auto median4 = [&](size_t end) {
    std::array<double, 4> v{ms[end - 4], ms[end - 3], ms[end - 2], ms[end - 1]};
    std::sort(v.begin(), v.end());
    return 0.5 * (v[1] + v[2]);
  };
  for (;;) {
    ms.push_back(frame());
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed < seconds) continue;
    if (elapsed >= 4.0 * seconds || !std::isfinite(ms.back())) break;  // no timestamps: nothing to watch
    if (ms.size() >= 8 && median4(ms.size()) >= 0.98 * median4(ms.size() - 4)) break;
  }
  return uint32_t(ms.size());
}

}  // namespace prismoid::app
