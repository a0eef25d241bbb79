#include "renderer/vk/timer.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"

namespace prismoid::vk {

GpuTimer::GpuTimer(const Device& device, uint32_t max_passes)
    : device_(&device), capacity_(max_passes), enabled_(device.capabilities().timestamps) {
  if (!enabled_) return;
  VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
  info.queryType = VK_QUERY_TYPE_TIMESTAMP;
  info.queryCount = 2 * max_passes;
  VkQueryPool pool;
  check(vkCreateQueryPool(device.get(), &info, nullptr, &pool), "vkCreateQueryPool");
  pool_ = UniqueQueryPool(device.get(), pool);
}

void GpuTimer::reset(VkCommandBuffer cmd) {
  names_.clear();
  open_ = false;
  if (enabled_) vkCmdResetQueryPool(cmd, pool_.get(), 0, 2 * capacity_);
}

void GpuTimer::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  device_->submit_and_wait([&](VkCommandBuffer cmd) {
    reset(cmd);
    record(cmd);
  });
}

void GpuTimer::begin(VkCommandBuffer cmd, std::string name) {
  if (open_) throw std::logic_error("GpuTimer: pass '" + name + "' begins inside pass '" + names_.back() + "'");
  if (names_.size() >= capacity_) throw std::logic_error("GpuTimer: more passes than the timer was made for");
  const auto index = static_cast<uint32_t>(names_.size());
  names_.push_back(std::move(name));
  open_ = true;
  if (enabled_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_.get(), 2 * index);
}

void GpuTimer::end(VkCommandBuffer cmd) {
  if (!open_) throw std::logic_error("GpuTimer: end without begin");
  open_ = false;
  const auto index = static_cast<uint32_t>(names_.size() - 1);
  if (enabled_) vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, pool_.get(), 2 * index + 1);
}

std::vector<PassTiming> GpuTimer::read() const {
  std::vector<PassTiming> result;
  if (names_.empty()) return result;
  std::vector<uint64_t> ticks(2 * names_.size());
  if (enabled_) {
    check(vkGetQueryPoolResults(device_->get(), pool_.get(), 0, static_cast<uint32_t>(ticks.size()),
                                ticks.size() * sizeof(uint64_t), ticks.data(), sizeof(uint64_t),
                                VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
  }
  const double ns_per_tick = device_->capabilities().timestamp_period_ns;
  for (size_t i = 0; i < names_.size(); ++i) {
    double ms = std::numeric_limits<double>::quiet_NaN();
    if (enabled_) ms = static_cast<double>(ticks[2 * i + 1] - ticks[2 * i]) * ns_per_tick * 1e-6;
    result.push_back({names_[i], ms});
  }
  return result;
}

}  // namespace prismoid::vk
