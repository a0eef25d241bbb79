#pragma once
// Front-to-back order of tetrahedra, each frame, on the GPU: keys from the eye's distance to
// each cell's centroid, then the radix sort of renderer/sort.
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
#include "renderer/sort/radix_sort.hpp"

namespace prismoid::vk {
class Device;
class GpuTimer;
}  // namespace prismoid::vk

namespace prismoid::volume {

// Front-to-back order of a tetrahedral mesh: key = each tetrahedron's centroid's squared
// distance from the eye minus the mesh origin's (|m|^2 - 2 m.e, mesh-local: no cancellation
// however far the eye), as order-preserving unsigned bits (sort_key_bits), value = tet index;
// then the radix sort. `positions` (vec4 per point, xyz in the
// mesh's local frame) and `tets` (uvec4 per cell) are the buffers of volume::GpuTetMesh;
// `eye_local` is the eye in that same local frame.
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
  sort::GpuRadixSort sort_;
  vk::UniqueDescriptorSetLayout keys_set_layout_;
  vk::UniquePipelineLayout keys_layout_;
  vk::UniquePipeline keys_pipeline_;
  vk::DescriptorSet keys_set_;
  vk::Buffer keys_;
  vk::Buffer order_;
  uint32_t capacity_ = 0;
};

}  // namespace prismoid::volume
