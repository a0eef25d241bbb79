#pragma once
// Sorting on the GPU, shared by whoever needs it (the volume visibility sort, the compute
// backend's tile lists, FastAtlas's pre-order): a stable radix sort of (key, value) pairs in
// compute shaders (shaders/sort/), and the float keys it orders.
//
// Recording rules: record() updates descriptor sets, so call it at most once per command buffer
// and only after the GPU finished the previous submission that used this object (offscreen:
// Device::submit_and_wait; the window: the frame's fence). Growing destroys the old buffers at
// once, which relies on the same rule.
#include <cstdint>

#include <vulkan/vulkan.h>

#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"

namespace prismoid::vk {
class Device;
}  // namespace prismoid::vk

namespace prismoid::sort {

// Stable LSD radix sort of (uint32 key, uint32 value) pairs, ascending by key, on the GPU:
// 4 passes of 8 bits, each a per-block digit histogram, a reduce-then-scan of the
// histograms and a stable scatter. Uses only core Vulkan 1.3 compute (no subgroup
// operations). At most 65535 * 1024 keys (the dispatch-size minimum every device offers),
// and as many as the device's storage-buffer range allows.
class GpuRadixSort {
 public:
  GpuRadixSort(const vk::Device& device, uint32_t capacity);

  // Sorts the first `count` pairs of the two storage buffers in place (count <= capacity).
  // Ends with a barrier that makes the result visible to later compute and mesh-shader
  // reads (and transfers). Waits for earlier compute and transfer writes to the buffers.
  void record(VkCommandBuffer cmd, const vk::Buffer& keys, const vk::Buffer& values, uint32_t count);
  // The same, for a count an earlier pass wrote in device memory: uint32 number `count_index`
  // of `count`, cut to `max_count` (<= capacity; the key and value buffers hold at least that
  // many). No read back: a setup kernel turns the count into the kernels' parameters and the
  // group counts of indirect dispatches. Waits for earlier compute and transfer writes to the
  // three buffers.
  void record_indirect(VkCommandBuffer cmd, const vk::Buffer& keys, const vk::Buffer& values, const vk::Buffer& count,
                       uint32_t count_index, uint32_t max_count);

  // Grows the scratch buffers to hold `capacity` pairs; never shrinks.
  void reserve(uint32_t capacity);
  uint32_t capacity() const { return capacity_; }
  // Device memory this sort holds (scratch, histograms, parameters), and what it would hold
  // for `capacity` pairs.
  uint64_t bytes() const;
  static uint64_t scratch_bytes(uint32_t capacity);

 private:
  void bind_caller_buffers(VkBuffer keys, VkBuffer values);
  void check_caller_buffers(const vk::Buffer& keys, const vk::Buffer& values, uint32_t count) const;
  // The 4 digit passes; dispatch sizes from the arguments, or from params_ when indirect.
  void record_passes(VkCommandBuffer cmd, const VkBuffer (&caller)[2], bool indirect, uint32_t blocks, uint32_t scan_groups);

  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline histogram_;
  vk::UniquePipeline scan_reduce_;
  vk::UniquePipeline scan_partials_;
  vk::UniquePipeline scan_downsweep_;
  vk::UniquePipeline scatter_;
  vk::UniquePipeline setup_;  // record_indirect(): the count in device memory -> params_
  // Even passes read the caller's buffers and write scratch, odd passes the reverse.
  vk::DescriptorSet pass_sets_[2];
  vk::Buffer scratch_keys_;
  vk::Buffer scratch_values_;
  vk::Buffer histograms_;
  vk::Buffer partials_;
  vk::Buffer params_;  // gpu::RadixSortParams: the key count and the indirect dispatches
  uint32_t capacity_ = 0;
};

// The unsigned key that orders like the float `key` (negative floats bit-inverted, the others
// with the sign bit set), and back: what the keys pass writes.
uint32_t sort_key_bits(float key);
float sort_key_value(uint32_t bits);

// The stages that may read what a sort wrote: compute and copies, and the mesh (and task) shaders
// of the volume's interval pass where the device has them.
VkPipelineStageFlags2 sorted_readers_stages(const vk::Device& device);

}  // namespace prismoid::sort
