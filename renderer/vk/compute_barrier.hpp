#pragma once
// A compute dispatch's writes to `buffers` made visible to the next dispatch (the barrier's
// execution dependency also orders the next dispatch's writes after this one's reads): what the
// GPU sort, the prefix sum and the compute backend's tile passes chain their dispatches with.
#include <initializer_list>

#include <vulkan/vulkan.h>

#include "renderer/vk/memory.hpp"

namespace prismoid::vk {

inline void compute_to_compute(VkCommandBuffer cmd, std::initializer_list<VkBuffer> buffers) {
  buffer_barrier(cmd, buffers, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                 VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

}  // namespace prismoid::vk
