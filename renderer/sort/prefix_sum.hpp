#pragma once
// The exclusive prefix sum of uint32 values on the GPU, in place: the radix sort's
// reduce-then-scan kernels (shaders/sort/radix_scan_*.comp) run on the caller's buffer. The
// compute backend turns its per-cell pair counts into each cell's first pair with it.
//
// Recording rules as the radix sort's (radix_sort.hpp): record() updates a descriptor set, so
// call it at most once per command buffer and only after the GPU finished the previous
// submission that used this object; growing destroys the old scratch at once.
#include <cstdint>

#include <vulkan/vulkan.h>

#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"

namespace prismoid::vk {
class Device;
}  // namespace prismoid::vk

namespace prismoid::sort {

class GpuPrefixSum {
 public:
  explicit GpuPrefixSum(const vk::Device& device);

  // The most values one sum takes: 65535 blocks (the dispatch-size minimum every device offers).
  static uint64_t max_count();
  // Replaces the first `count` (1..max_count()) uint32 of `values` by their exclusive prefix
  // sums. Waits for earlier compute writes to `values`; ends with a barrier that makes the sums
  // visible to later compute reads and writes.
  void record(VkCommandBuffer cmd, const vk::Buffer& values, uint32_t count);

  // Grows the scratch to sum `count` values; never shrinks.
  void reserve(uint64_t count);
  // Device memory it holds (block partials, parameters), and what it would hold for `count` values.
  uint64_t bytes() const;
  static uint64_t bytes_for(uint64_t count);

 private:
  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline reduce_, partials_pass_, downsweep_;
  vk::DescriptorSet set_;
  vk::Buffer partials_;  // one uint32 per block of PRISMOID_SORT_SCAN_BLOCK values
  vk::Buffer params_;    // gpu::RadixSortParams: the count
  uint64_t capacity_ = 0;
};

}  // namespace prismoid::sort
