#include "renderer/sort/radix_sort.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/vk/compute_barrier.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "shaders/shared/sort.h"

namespace prismoid::sort {

namespace {

constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;

const std::array<vk::DescriptorBinding, 8> kSortBindings = {{
    {PRISMOID_SORT_BINDING_KEYS_IN, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_BINDING_VALUES_IN, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_BINDING_KEYS_OUT, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_BINDING_VALUES_OUT, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_BINDING_HISTOGRAMS, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_BINDING_PARTIALS, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_BINDING_PARAMS, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
    {PRISMOID_SORT_BINDING_COUNT, kStorage, VK_SHADER_STAGE_COMPUTE_BIT},
}};

}  // namespace

VkPipelineStageFlags2 sorted_readers_stages(const vk::Device& device) {
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT;
  if (device.capabilities().mesh_shader) stages |= VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT;
  if (device.capabilities().task_shader) stages |= VK_PIPELINE_STAGE_2_TASK_SHADER_BIT_EXT;
  return stages;
}

namespace {

uint32_t blocks_for(uint32_t count) {
  return static_cast<uint32_t>((uint64_t(count) + PRISMOID_SORT_BLOCK - 1) / PRISMOID_SORT_BLOCK);  // no wrap near 2^32
}

struct StorageWrite {
  VkDescriptorSet set;
  uint32_t binding;
  VkBuffer buffer;
};

// One vkUpdateDescriptorSets call for all of them.
void write_storage_buffers(const vk::Device& device, std::initializer_list<StorageWrite> writes) {
  std::vector<VkDescriptorBufferInfo> infos;
  infos.reserve(writes.size());  // the writes point into it
  std::vector<VkWriteDescriptorSet> list;
  for (const StorageWrite& w : writes) {
    infos.push_back({w.buffer, 0, VK_WHOLE_SIZE});
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = w.set;
    write.dstBinding = w.binding;
    write.descriptorCount = 1;
    write.descriptorType = kStorage;
    write.pBufferInfo = &infos.back();
    list.push_back(write);
  }
  vkUpdateDescriptorSets(device.get(), static_cast<uint32_t>(list.size()), list.data(), 0, nullptr);
}

}  // namespace

GpuRadixSort::GpuRadixSort(const vk::Device& device, uint32_t capacity) : device_(device) {
  set_layout_ = vk::create_descriptor_set_layout(device, kSortBindings);
  VkDescriptorSetLayout sets[] = {set_layout_.get()};
  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::RadixSortPush)};
  layout_ = vk::create_pipeline_layout(device, sets, std::span(&push, 1));
  histogram_ = vk::create_compute_pipeline(device, "sort/radix_histogram.comp", layout_.get());
  scan_reduce_ = vk::create_compute_pipeline(device, "sort/radix_scan_reduce.comp", layout_.get());
  scan_partials_ = vk::create_compute_pipeline(device, "sort/radix_scan_partials.comp", layout_.get());
  scan_downsweep_ = vk::create_compute_pipeline(device, "sort/radix_scan_downsweep.comp", layout_.get());
  scatter_ = vk::create_compute_pipeline(device, "sort/radix_scatter.comp", layout_.get());
  static_assert(sizeof(gpu::RadixSetupPush) == sizeof(gpu::RadixSortPush), "the setup kernel shares the sort's layout");
  setup_ = vk::create_compute_pipeline(device, "sort/radix_setup.comp", layout_.get());
  for (auto& s : pass_sets_) s = vk::allocate_descriptor_set(device, set_layout_.get(), kSortBindings);
  params_ = vk::Buffer(device, sizeof(gpu::RadixSortParams),
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                       vk::MemoryUse::DeviceLocal);
  // The count binding names the parameters until record_indirect() names a count buffer.
  for (const auto& s : pass_sets_)
    write_storage_buffers(device, {{s.set, PRISMOID_SORT_BINDING_PARAMS, params_.get()}, {s.set, PRISMOID_SORT_BINDING_COUNT, params_.get()}});
  reserve(std::max(capacity, 1u));
}

void GpuRadixSort::reserve(uint32_t capacity) {
  if (capacity_ > 0 && capacity <= capacity_) return;
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(device_.physical(), &props);
  const uint32_t blocks = blocks_for(capacity);
  const uint64_t bytes = uint64_t(blocks) * PRISMOID_SORT_BLOCK * sizeof(uint32_t);
  if (blocks > props.limits.maxComputeWorkGroupCount[0] || bytes > props.limits.maxStorageBufferRange)
    throw vk::NoSuitableDevice(device_.capabilities().name + " cannot radix-sort " + std::to_string(capacity) +
                               " keys in one dispatch (at most " + std::to_string(props.limits.maxComputeWorkGroupCount[0]) +
                               " workgroups of " + std::to_string(PRISMOID_SORT_BLOCK) + " keys and " +
                               std::to_string(props.limits.maxStorageBufferRange) + " bytes per buffer)");
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  const uint64_t entries = uint64_t(blocks) * PRISMOID_SORT_RADIX;
  const uint64_t partials = (entries + PRISMOID_SORT_SCAN_BLOCK - 1) / PRISMOID_SORT_SCAN_BLOCK;
  scratch_keys_ = vk::Buffer(device_, bytes, usage, vk::MemoryUse::DeviceLocal);
  scratch_values_ = vk::Buffer(device_, bytes, usage, vk::MemoryUse::DeviceLocal);
  histograms_ = vk::Buffer(device_, entries * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
  partials_ = vk::Buffer(device_, partials * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
  capacity_ = blocks * PRISMOID_SORT_BLOCK;
  const VkDescriptorSet even = pass_sets_[0].set, odd = pass_sets_[1].set;
  write_storage_buffers(device_, {
      {even, PRISMOID_SORT_BINDING_KEYS_OUT, scratch_keys_.get()},
      {even, PRISMOID_SORT_BINDING_VALUES_OUT, scratch_values_.get()},
      {odd, PRISMOID_SORT_BINDING_KEYS_IN, scratch_keys_.get()},
      {odd, PRISMOID_SORT_BINDING_VALUES_IN, scratch_values_.get()},
      {even, PRISMOID_SORT_BINDING_HISTOGRAMS, histograms_.get()},
      {odd, PRISMOID_SORT_BINDING_HISTOGRAMS, histograms_.get()},
      {even, PRISMOID_SORT_BINDING_PARTIALS, partials_.get()},
      {odd, PRISMOID_SORT_BINDING_PARTIALS, partials_.get()},
  });
}

// Written on every record, not cached by handle: a destroyed buffer's handle can come back
// for a new buffer, and a cache would then keep the stale descriptor.
void GpuRadixSort::bind_caller_buffers(VkBuffer keys, VkBuffer values) {
  const VkDescriptorSet even = pass_sets_[0].set, odd = pass_sets_[1].set;
  write_storage_buffers(device_, {
      {even, PRISMOID_SORT_BINDING_KEYS_IN, keys},
      {even, PRISMOID_SORT_BINDING_VALUES_IN, values},
      {odd, PRISMOID_SORT_BINDING_KEYS_OUT, keys},
      {odd, PRISMOID_SORT_BINDING_VALUES_OUT, values},
  });
}

uint64_t GpuRadixSort::bytes() const {
  return scratch_keys_.size() + scratch_values_.size() + histograms_.size() + partials_.size() + params_.size();
}

uint64_t GpuRadixSort::scratch_bytes(uint32_t capacity) {
  const uint64_t blocks = (uint64_t(capacity) + PRISMOID_SORT_BLOCK - 1) / PRISMOID_SORT_BLOCK;
  const uint64_t entries = blocks * PRISMOID_SORT_RADIX;
  const uint64_t partials = (entries + PRISMOID_SORT_SCAN_BLOCK - 1) / PRISMOID_SORT_SCAN_BLOCK;
  return 2 * blocks * PRISMOID_SORT_BLOCK * sizeof(uint32_t) + (entries + partials) * sizeof(uint32_t) + sizeof(gpu::RadixSortParams);
}

void GpuRadixSort::check_caller_buffers(const vk::Buffer& keys, const vk::Buffer& values, uint32_t count) const {
  if (count > capacity_)
    throw std::invalid_argument("GpuRadixSort: " + std::to_string(count) + " keys exceed the capacity " + std::to_string(capacity_));
  if (keys.size() < VkDeviceSize(count) * sizeof(uint32_t) || values.size() < VkDeviceSize(count) * sizeof(uint32_t))
    throw std::invalid_argument("GpuRadixSort: the key or value buffer holds fewer than " + std::to_string(count) + " entries");
}

void GpuRadixSort::record(VkCommandBuffer cmd, const vk::Buffer& keys, const vk::Buffer& values, uint32_t count) {
  check_caller_buffers(keys, values, count);
  const VkBuffer caller[] = {keys.get(), values.get()};
  vk::buffer_barrier(cmd, {caller[0], caller[1]},
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT | sorted_readers_stages(device_),
                 VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  if (count > 1) {
    bind_caller_buffers(keys.get(), values.get());
    const uint32_t blocks = blocks_for(count);
    const uint32_t entries = blocks * PRISMOID_SORT_RADIX;
    const uint32_t scan_groups = (entries + PRISMOID_SORT_SCAN_BLOCK - 1) / PRISMOID_SORT_SCAN_BLOCK;
    // The count is known here: the parameters go in with the commands (an earlier sort's
    // kernels, or indirect dispatches, must be done reading them).
    const gpu::RadixSortParams params{glm::uvec4(count, 0u, blocks, entries), glm::uvec4(blocks, 1u, 1u, 0u),
                                      glm::uvec4(scan_groups, 1u, 1u, 0u)};
    vk::buffer_barrier(cmd, {params_.get()}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                       VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdUpdateBuffer(cmd, params_.get(), 0, sizeof(params), &params);
    vk::buffer_barrier(cmd, {params_.get()}, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    record_passes(cmd, caller, false, blocks, scan_groups);
  }
  vk::buffer_barrier(cmd, {caller[0], caller[1]}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 sorted_readers_stages(device_), VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
}

void GpuRadixSort::record_indirect(VkCommandBuffer cmd, const vk::Buffer& keys, const vk::Buffer& values, const vk::Buffer& count,
                                   uint32_t count_index, uint32_t max_count) {
  check_caller_buffers(keys, values, max_count);
  if (count.size() < (VkDeviceSize(count_index) + 1) * sizeof(uint32_t))
    throw std::invalid_argument("GpuRadixSort: the count buffer holds no entry " + std::to_string(count_index));
  const VkBuffer caller[] = {keys.get(), values.get()};
  vk::buffer_barrier(cmd, {caller[0], caller[1], count.get()},
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT | sorted_readers_stages(device_),
                 VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                 VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  bind_caller_buffers(keys.get(), values.get());
  write_storage_buffers(device_, {{pass_sets_[0].set, PRISMOID_SORT_BINDING_COUNT, count.get()}});
  // An earlier sort's kernels and indirect dispatches must be done with the parameters.
  vk::buffer_barrier(cmd, {params_.get()}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                     VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  const gpu::RadixSetupPush setup{glm::uvec4(count_index, max_count, 0u, 0u)};
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &pass_sets_[0].set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(setup), &setup);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, setup_.get());
  vkCmdDispatch(cmd, 1, 1, 1);
  vk::buffer_barrier(cmd, {params_.get()}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
  record_passes(cmd, caller, true, 0, 0);
  vk::buffer_barrier(cmd, {caller[0], caller[1]}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 sorted_readers_stages(device_), VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
}

void GpuRadixSort::record_passes(VkCommandBuffer cmd, const VkBuffer (&caller)[2], bool indirect, uint32_t blocks,
                                 uint32_t scan_groups) {
  const VkBuffer scratch[] = {scratch_keys_.get(), scratch_values_.get()};
  const auto dispatch = [&](VkPipeline pipeline, uint32_t groups, VkDeviceSize indirect_offset) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    if (indirect) vkCmdDispatchIndirect(cmd, params_.get(), indirect_offset);
    else vkCmdDispatch(cmd, groups, 1, 1);
  };
  const VkDeviceSize block_dispatch = offsetof(gpu::RadixSortParams, block_dispatch);
  const VkDeviceSize scan_dispatch = offsetof(gpu::RadixSortParams, scan_dispatch);
  for (uint32_t pass = 0; pass < PRISMOID_SORT_PASSES; ++pass) {
    const VkBuffer* out = pass % 2 == 0 ? scratch : caller;
    const gpu::RadixSortPush push{glm::uvec4(0u, pass * PRISMOID_SORT_RADIX_BITS, 0u, 0u)};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &pass_sets_[pass % 2].set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    dispatch(histogram_.get(), blocks, block_dispatch);
    vk::compute_to_compute(cmd, {histograms_.get()});
    dispatch(scan_reduce_.get(), scan_groups, scan_dispatch);
    vk::compute_to_compute(cmd, {partials_.get()});
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, scan_partials_.get());
    vkCmdDispatch(cmd, 1, 1, 1);
    vk::compute_to_compute(cmd, {partials_.get()});
    dispatch(scan_downsweep_.get(), scan_groups, scan_dispatch);
    vk::compute_to_compute(cmd, {histograms_.get()});
    dispatch(scatter_.get(), blocks, block_dispatch);
    if (pass + 1 < PRISMOID_SORT_PASSES) vk::compute_to_compute(cmd, {out[0], out[1]});
  }
}

uint32_t sort_key_bits(float key) {
  const auto bits = std::bit_cast<uint32_t>(key);
  return (bits & 0x80000000u) != 0u ? ~bits : bits | 0x80000000u;
}

float sort_key_value(uint32_t bits) { return std::bit_cast<float>((bits & 0x80000000u) != 0u ? bits & 0x7fffffffu : ~bits); }

}  // namespace prismoid::sort
