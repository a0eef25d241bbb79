#include "renderer/mixed/frame_stats.hpp"

namespace prismoid::mixed {

double FrameStats::passes_ms() const {
  double total = 0.0;
  for (const vk::PassTiming& p : passes) total += p.gpu_ms;
  return total;
}

}  // namespace prismoid::mixed
