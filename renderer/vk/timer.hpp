#pragma once
// GPU time per pass from timestamp queries: every pass a frame records is bracketed by a
// pair of timestamps, and its name travels with them into the stats.
#include <functional>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

#include "renderer/vk/handle.hpp"

namespace prismoid::vk {

class Device;

struct PassTiming {
  std::string name;
  double gpu_ms = 0.0;  // NaN where the device has no timestamps
};

// The passes' GPU time summed (NaN if any pass has none).
inline double total_gpu_ms(const std::vector<PassTiming>& passes) {
  double total = 0.0;
  for (const PassTiming& p : passes) total += p.gpu_ms;
  return total;
}

class GpuTimer {
 public:
  GpuTimer(const Device& device, uint32_t max_passes);

  void reset(VkCommandBuffer cmd);
  // One submission on the timer's device, waited for: reset(), then `record` (which brackets its
  // passes with this timer). The timings are then read().
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record);
  void begin(VkCommandBuffer cmd, std::string name);
  void end(VkCommandBuffer cmd);
  // Reads the timings of the passes recorded since reset(); waits for the GPU.
  std::vector<PassTiming> read() const;
  // Names of the passes recorded since reset(), in order.
  const std::vector<std::string>& recorded() const { return names_; }

 private:
  const Device* device_;
  UniqueQueryPool pool_;
  uint32_t capacity_;
  bool enabled_;
  bool open_ = false;
  std::vector<std::string> names_;
};

// Brackets the recording of one pass.
class ScopedPass {
 public:
  ScopedPass(GpuTimer& timer, VkCommandBuffer cmd, std::string name) : timer_(timer), cmd_(cmd) {
    timer_.begin(cmd_, std::move(name));
  }
  ~ScopedPass() { timer_.end(cmd_); }
  ScopedPass(const ScopedPass&) = delete;
  ScopedPass& operator=(const ScopedPass&) = delete;

 private:
  GpuTimer& timer_;
  VkCommandBuffer cmd_;
};

}  // namespace prismoid::vk
