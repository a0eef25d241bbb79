#include "renderer/volume/mesh/visibility_sort.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/timer.hpp"
#include "shaders/shared/sort.h"

namespace prismoid::volume {

namespace {

constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;

const std::array<vk::DescriptorBinding, 4> kKeysBindings = {{
    {PRISMOID_SORT_KEYS_BINDING_POSITIONS, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_KEYS_BINDING_TETS, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_KEYS_BINDING_KEYS, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_KEYS_BINDING_VALUES, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
}};

}  // namespace

VisibilitySort::VisibilitySort(const vk::Device& device) : device_(device), sort_(device, 0) {
  keys_set_layout_ = vk::create_descriptor_set_layout(device, kKeysBindings);
  VkDescriptorSetLayout sets[] = {keys_set_layout_.get()};
  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::SortKeysPush)};
  keys_layout_ = vk::create_pipeline_layout(device, sets, std::span(&push, 1));
  keys_pipeline_ = vk::create_compute_pipeline(device, "volume/sort_keys.comp", keys_layout_.get());
  keys_set_ = vk::allocate_descriptor_set(device, keys_set_layout_.get(), kKeysBindings);
  reserve(1);
}

void VisibilitySort::reserve(uint32_t tet_count) {
  if (tet_count <= capacity_) return;
  sort_.reserve(tet_count);
  capacity_ = sort_.capacity();
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  keys_ = vk::Buffer(device_, VkDeviceSize(capacity_) * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
  order_ = vk::Buffer(device_, VkDeviceSize(capacity_) * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
  vk::write_buffer_descriptor(device_, keys_set_.set, PRISMOID_SORT_KEYS_BINDING_KEYS, kStorage, keys_.get());
  vk::write_buffer_descriptor(device_, keys_set_.set, PRISMOID_SORT_KEYS_BINDING_VALUES, kStorage, order_.get());
}

void VisibilitySort::record(VkCommandBuffer cmd, const vk::Buffer& positions, const vk::Buffer& tets, uint32_t tet_count,
                            const glm::vec3& eye_local, vk::GpuTimer& timer) {
  reserve(tet_count);
  vk::ScopedPass pass(timer, cmd, "sort");
  if (tet_count > 0) {
    // Written on every record, like the sort's caller buffers (handles can be reused).
    vk::write_buffer_descriptor(device_, keys_set_.set, PRISMOID_SORT_KEYS_BINDING_POSITIONS, kStorage, positions.get());
    vk::write_buffer_descriptor(device_, keys_set_.set, PRISMOID_SORT_KEYS_BINDING_TETS, kStorage, tets.get());
    // The previous frame's readers of the order must finish before the keys pass rewrites it.
    vk::buffer_barrier(cmd, {keys_.get(), order_.get()}, sort::sorted_readers_stages(device_), VK_ACCESS_2_NONE,
                   VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    const gpu::SortKeysPush push{glm::vec4(eye_local, 1.0f), glm::uvec4(tet_count, 0u, 0u, 0u)};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, keys_pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, keys_layout_.get(), 0, 1, &keys_set_.set, 0, nullptr);
    vkCmdPushConstants(cmd, keys_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, static_cast<uint32_t>((uint64_t(tet_count) + PRISMOID_SORT_BLOCK - 1) / PRISMOID_SORT_BLOCK), 1, 1);
  }
  sort_.record(cmd, keys_, order_, tet_count);  // starts by waiting for the keys pass's writes
}

}  // namespace prismoid::volume
