#pragma once
// Front-to-back order of tetrahedra, each frame, on the GPU: keys from the eye's distance to
// each cell's centroid, then a radix sort in compute shaders.
//
// Recording rules (both classes): record() updates descriptor sets, so call it at most once
// per command buffer and only after the GPU finished the previous submission that used this
// object (offscreen: Device::submit_and_wait; the window: the frame's fence). Growing
// destroys the old buffers at once, which relies on the same rule.
#include <cstdint>
#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"

namespace prismoid::vk {
class Device;
class GpuTimer;
}  // namespace prismoid::vk

namespace prismoid::volume {

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

// Front-to-back order of a tetrahedral mesh: key = each tetrahedron's centroid's squared
// distance from the eye minus the mesh origin's (|m|^2 - 2 m.e, mesh-local: no cancellation
// however far the eye), as order-preserving unsigned bits (sort_key_bits), value = tet index;
// then the radix sort. `positions` (vec4 per point, xyz in the
// mesh's local frame) and `tets` (uvec4 per cell) are the buffers of volume::GpuTetMesh;
// `eye_local` is the eye in that same local frame.
// The unsigned key that orders like the float `key` (negative floats bit-inverted, the others
// with the sign bit set), and back: what the keys pass writes.
uint32_t sort_key_bits(float key);
float sort_key_value(uint32_t bits);

class VisibilitySort {
 public:
  explicit VisibilitySort(const vk::Device& device);

  // Records the keys pass and the sort as one timed pass named "sort". Grows its buffers
  // when tet_count exceeds the capacity (must not be called inside a render pass).
  void record(VkCommandBuffer cmd, const vk::Buffer& positions, const vk::Buffer& tets, uint32_t tet_count,
              const glm::vec3& eye_local, vk::GpuTimer& timer);

  const vk::Buffer& order() const { return order_; }  // uint32 tet indices, nearest centroid first
  const vk::Buffer& keys() const { return keys_; }    // the sorted keys (for tests)

 private:
  void reserve(uint32_t tet_count);

  const vk::Device& device_;
  GpuRadixSort sort_;
  vk::UniqueDescriptorSetLayout keys_set_layout_;
  vk::UniquePipelineLayout keys_layout_;
  vk::UniquePipeline keys_pipeline_;
  vk::DescriptorSet keys_set_;
  vk::Buffer keys_;
  vk::Buffer order_;
  uint32_t capacity_ = 0;
};

}  // namespace prismoid::volume
