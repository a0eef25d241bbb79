#pragma once
// The logical device: one graphics+compute queue, the features Prismoid's modes use, and
// helpers to record and submit work.
#include <functional>
#include <vulkan/vulkan.h>

#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/handle.hpp"

namespace prismoid::vk {

class Instance;

struct DeviceOptions {
  bool presentation = false;  // enable VK_KHR_swapchain
};

class Device {
 public:
  Device(const Instance& instance, const DeviceCapabilities& caps, const DeviceOptions& options);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkDevice get() const { return device_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkInstance instance() const { return instance_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return caps_.queue_family; }
  const DeviceCapabilities& capabilities() const { return caps_; }
  VkCommandPool command_pool() const { return command_pool_.get(); }

  // Index of a memory type allowed by `type_bits` with all of `flags`; throws if none.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const;
  VkFormatProperties format_properties(VkFormat format) const;

  // Records `record` into a fresh command buffer, submits it and waits for completion.
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const;
  void wait_idle() const;

  // True when ray-tracing pipelines, acceleration structures and buffer device addresses are
  // enabled (caps.ray_tracing()); the ray-tracing entry points below are then loaded.
  bool ray_tracing_enabled() const { return ray_tracing_; }

  // Extension entry points (null when the extension is not enabled).
  PFN_vkCmdDrawMeshTasksEXT cmd_draw_mesh_tasks = nullptr;
  PFN_vkCreateAccelerationStructureKHR create_acceleration_structure = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR get_acceleration_structure_build_sizes = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR get_acceleration_structure_device_address = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR cmd_build_acceleration_structures = nullptr;
  PFN_vkCmdWriteAccelerationStructuresPropertiesKHR cmd_write_acceleration_structures_properties = nullptr;
  PFN_vkCmdCopyAccelerationStructureKHR cmd_copy_acceleration_structure = nullptr;
  PFN_vkCreateRayTracingPipelinesKHR create_ray_tracing_pipelines = nullptr;
  PFN_vkGetRayTracingShaderGroupHandlesKHR get_ray_tracing_shader_group_handles = nullptr;
  PFN_vkCmdTraceRaysKHR cmd_trace_rays = nullptr;
  PFN_vkCmdTraceRaysIndirectKHR cmd_trace_rays_indirect = nullptr;  // with caps.trace_rays_indirect

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  DeviceCapabilities caps_;
  bool ray_tracing_ = false;
  VkPhysicalDeviceMemoryProperties memory_{};
  UniqueCommandPool command_pool_;
};

}  // namespace prismoid::vk
