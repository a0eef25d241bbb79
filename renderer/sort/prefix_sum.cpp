#include "renderer/sort/prefix_sum.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <stdexcept>
#include <string>

#include "renderer/vk/compute_barrier.hpp"
#include "renderer/vk/device.hpp"
#include "shaders/shared/sort.h"

namespace prismoid::sort {

namespace {

constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;
constexpr uint64_t kMaxGroups = 65535;

const std::array<vk::DescriptorBinding, 3> kBindings = {{
    {PRISMOID_SORT_BINDING_HISTOGRAMS, kStorage, kCompute},
    {PRISMOID_SORT_BINDING_PARTIALS, kStorage, kCompute},
    {PRISMOID_SORT_BINDING_PARAMS, kStorage, kCompute},
}};

uint64_t blocks_for(uint64_t count) { return (count + PRISMOID_SORT_SCAN_BLOCK - 1) / PRISMOID_SORT_SCAN_BLOCK; }

}  // namespace

GpuPrefixSum::GpuPrefixSum(const vk::Device& device) : device_(device) {
  set_layout_ = vk::create_descriptor_set_layout(device, kBindings);
  VkDescriptorSetLayout sets[] = {set_layout_.get()};
  VkPushConstantRange push{kCompute, 0, sizeof(gpu::RadixSortPush)};
  layout_ = vk::create_pipeline_layout(device, sets, std::span(&push, 1));
  reduce_ = vk::create_compute_pipeline(device, "sort/radix_scan_reduce.comp", layout_.get());
  partials_pass_ = vk::create_compute_pipeline(device, "sort/radix_scan_partials.comp", layout_.get());
  downsweep_ = vk::create_compute_pipeline(device, "sort/radix_scan_downsweep.comp", layout_.get());
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), kBindings);
  params_ = vk::Buffer(device, sizeof(gpu::RadixSortParams), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       vk::MemoryUse::DeviceLocal);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SORT_BINDING_PARAMS, kStorage, params_.get());
}

uint64_t GpuPrefixSum::max_count() { return kMaxGroups * PRISMOID_SORT_SCAN_BLOCK; }

void GpuPrefixSum::reserve(uint64_t count) {
  count = std::max<uint64_t>(count, 1);
  if (count <= capacity_) return;
  partials_ = vk::Buffer(device_, blocks_for(count) * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::DeviceLocal);
  vk::write_buffer_descriptor(device_, set_.set, PRISMOID_SORT_BINDING_PARTIALS, kStorage, partials_.get());
  capacity_ = count;
}

uint64_t GpuPrefixSum::bytes() const { return partials_.size() + params_.size(); }

uint64_t GpuPrefixSum::bytes_for(uint64_t count) {
  return blocks_for(std::max<uint64_t>(count, 1)) * sizeof(uint32_t) + sizeof(gpu::RadixSortParams);
}

void GpuPrefixSum::record(VkCommandBuffer cmd, const vk::Buffer& values, uint32_t count) {
  if (count == 0 || count > max_count() || count > capacity_ || values.size() < uint64_t(count) * sizeof(uint32_t))
    throw std::logic_error("GpuPrefixSum: " + std::to_string(count) + " values do not fit its scratch or the buffer");
  vk::write_buffer_descriptor(device_, set_.set, PRISMOID_SORT_BINDING_HISTOGRAMS, kStorage, values.get());
  const uint32_t groups = static_cast<uint32_t>(blocks_for(count));
  const gpu::RadixSortParams params{glm::uvec4(count, 0u, 0u, count), glm::uvec4(0u), glm::uvec4(0u)};
  vkCmdUpdateBuffer(cmd, params_.get(), 0, sizeof(params), &params);
  vk::buffer_barrier(cmd, {params_.get()}, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  const gpu::RadixSortPush push{glm::uvec4(0u)};
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), kCompute, 0, sizeof(push), &push);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, reduce_.get());
  vkCmdDispatch(cmd, groups, 1, 1);
  vk::compute_to_compute(cmd, {partials_.get()});
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, partials_pass_.get());
  vkCmdDispatch(cmd, 1, 1, 1);
  vk::compute_to_compute(cmd, {partials_.get()});
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, downsweep_.get());
  vkCmdDispatch(cmd, groups, 1, 1);
  vk::compute_to_compute(cmd, {values.get()});
}

}  // namespace prismoid::sort
