#pragma once
// Ray-tracing pipelines and their shader binding tables.
//
// Shader binding table layout (the rules of VK_KHR_ray_tracing_pipeline): every region starts at
// a multiple of shaderGroupBaseAlignment; records within a region are `stride` apart, a multiple
// of shaderGroupHandleAlignment and at least shaderGroupHandleSize; the ray-generation region
// names one record and its size equals its stride. To choose among several ray-generation
// shaders by address, each ray-generation record gets a stride rounded up to the base alignment.
// The numbers come from the device (lavapipe: handle 32, alignment 16, base 32; NVIDIA: 32, 32,
// 64), never from constants.
#include <cstdint>
#include <string_view>
#include <vector>
#include <vulkan/vulkan.h>

#include "renderer/vk/handle.hpp"
#include "renderer/vk/memory.hpp"

namespace prismoid::vk {
class Device;
}

namespace prismoid::rt {

struct ShaderGroupProperties {
  uint32_t handle_size = 0;
  uint32_t handle_alignment = 0;
  uint32_t base_alignment = 0;
};

struct SbtRegion {
  VkDeviceSize offset = 0;  // from the table's (base-aligned) start
  VkDeviceSize stride = 0;
  VkDeviceSize size = 0;    // stride * records (0 for an empty region)
  uint32_t records = 0;
};

struct SbtLayout {
  SbtRegion raygen, miss, hit;
  VkDeviceSize bytes = 0;  // the whole table
};

// Throws std::invalid_argument for properties that are zero or not powers of two, or for no
// ray-generation shader.
SbtLayout layout_shader_binding_table(const ShaderGroupProperties& props, uint32_t raygen_count, uint32_t miss_count,
                                      uint32_t hit_count);

// One triangle hit group: a closest-hit and/or an any-hit shader (names under shaders/, either
// may be empty).
struct HitGroup {
  std::string_view closest_hit;
  std::string_view any_hit;
};

struct RayTracingPipelineDesc {
  std::vector<std::string_view> raygen;  // at least one
  std::vector<std::string_view> miss;
  std::vector<HitGroup> hit_groups;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  uint32_t max_recursion_depth = 1;  // traceRayEXT from ray-generation shaders only
};

class RayTracingPipeline {
 public:
  // Throws vk::NoSuitableDevice when the device has no ray tracing enabled, std::invalid_argument
  // for a recursion depth beyond the device's limit.
  RayTracingPipeline(const vk::Device& device, const RayTracingPipelineDesc& desc);

  VkPipeline get() const { return pipeline_.get(); }
  const SbtLayout& sbt_layout() const { return layout_; }
  VkDeviceAddress sbt_address() const { return sbt_address_; }

  // Records vkCmdTraceRaysKHR with ray-generation record `raygen` over width x height x depth
  // (the pipeline and its descriptors must be bound). Throws std::invalid_argument for a
  // raygen index out of range or a launch beyond the device's invocation limit.
  void trace(VkCommandBuffer cmd, uint32_t raygen, uint32_t width, uint32_t height, uint32_t depth = 1) const;
  // Records vkCmdTraceRaysIndirectKHR: the launch size is the VkTraceRaysIndirectCommandKHR at
  // `command` (a buffer made with INDIRECT_BUFFER and SHADER_DEVICE_ADDRESS usage), written on
  // the GPU; the writer keeps it within the device's invocation limit. Throws
  // vk::NoSuitableDevice without caps.trace_rays_indirect.
  void trace_indirect(VkCommandBuffer cmd, uint32_t raygen, VkDeviceAddress command) const;

 private:
  // The shader binding table's regions for a launch of ray-generation record `raygen`.
  struct Regions {
    VkStridedDeviceAddressRegionKHR raygen{}, miss{}, hit{}, callable{};
  };
  Regions regions(uint32_t raygen) const;

  const vk::Device* device_ = nullptr;
  vk::UniquePipeline pipeline_;
  vk::Buffer sbt_;
  VkDeviceAddress sbt_address_ = 0;
  SbtLayout layout_;
};

}  // namespace prismoid::rt
