#include "renderer/vk/device.hpp"

#include <string>
#include <type_traits>
#include <vector>

#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"

namespace prismoid::vk {

Device::Device(const Instance& instance, const DeviceCapabilities& caps, const DeviceOptions& options)
    : instance_(instance.get()), caps_(caps) {
  uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance_, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  check(vkEnumeratePhysicalDevices(instance_, &count, devices.data()), "vkEnumeratePhysicalDevices");
  if (caps.index >= count) throw NoSuitableDevice("device " + std::to_string(caps.index) + " disappeared");
  physical_ = devices[caps.index];
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

  std::vector<const char*> extensions;
  if (caps.mesh_shader) extensions.push_back(VK_EXT_MESH_SHADER_EXTENSION_NAME);
  if (options.presentation) {
    if (!caps.swapchain) throw NoSuitableDevice(caps.name + " cannot present to a window (no VK_KHR_swapchain)");
    extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
  }

  // Ray tracing (renderer/rt) when the device has all of it; ray queries are never enabled
  // (the GPU machines lack them), so every ray is traced through a ray-tracing pipeline.
  ray_tracing_ = caps.ray_tracing();
  if (ray_tracing_) {
    extensions.push_back(VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME);
    extensions.push_back(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
    extensions.push_back(VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
  }

  VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
  mesh.meshShader = caps.mesh_shader;
  mesh.taskShader = caps.task_shader;
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  as.accelerationStructure = VK_TRUE;
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  rt.rayTracingPipeline = VK_TRUE;
  rt.rayTracingPipelineTraceRaysIndirect = caps.trace_rays_indirect ? VK_TRUE : VK_FALSE;
  rt.pNext = &as;
  VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  v13.dynamicRendering = VK_TRUE;
  v13.synchronization2 = VK_TRUE;
  v13.maintenance4 = VK_TRUE;
  void** next = &v13.pNext;
  if (caps.mesh_shader) { *next = &mesh; next = &mesh.pNext; }
  if (ray_tracing_) *next = &rt;
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  v12.hostQueryReset = VK_TRUE;
  v12.bufferDeviceAddress = caps.buffer_device_address ? VK_TRUE : VK_FALSE;
  v12.pNext = &v13;
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features.pNext = &v12;
  features.features.pipelineStatisticsQuery = caps.pipeline_statistics ? VK_TRUE : VK_FALSE;
  features.features.geometryShader = caps.geometry_shader ? VK_TRUE : VK_FALSE;  // gl_PrimitiveID in fragment shaders
  features.features.fragmentStoresAndAtomics = caps.fragment_stores ? VK_TRUE : VK_FALSE;

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = caps.queue_family;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;

  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &features;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue_info;
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, caps.queue_family, 0, &queue_);

  if (caps.mesh_shader)
    cmd_draw_mesh_tasks = reinterpret_cast<PFN_vkCmdDrawMeshTasksEXT>(vkGetDeviceProcAddr(device_, "vkCmdDrawMeshTasksEXT"));
  if (ray_tracing_) {
    auto load = [this](auto& pfn, const char* name) {
      pfn = reinterpret_cast<std::remove_reference_t<decltype(pfn)>>(vkGetDeviceProcAddr(device_, name));
      if (!pfn) throw VulkanError(std::string("vkGetDeviceProcAddr(") + name + ")", VK_ERROR_EXTENSION_NOT_PRESENT);
    };
    load(create_acceleration_structure, "vkCreateAccelerationStructureKHR");
    load(get_acceleration_structure_build_sizes, "vkGetAccelerationStructureBuildSizesKHR");
    load(get_acceleration_structure_device_address, "vkGetAccelerationStructureDeviceAddressKHR");
    load(cmd_build_acceleration_structures, "vkCmdBuildAccelerationStructuresKHR");
    load(cmd_write_acceleration_structures_properties, "vkCmdWriteAccelerationStructuresPropertiesKHR");
    load(cmd_copy_acceleration_structure, "vkCmdCopyAccelerationStructureKHR");
    load(create_ray_tracing_pipelines, "vkCreateRayTracingPipelinesKHR");
    load(get_ray_tracing_shader_group_handles, "vkGetRayTracingShaderGroupHandlesKHR");
    load(cmd_trace_rays, "vkCmdTraceRaysKHR");
    if (caps.trace_rays_indirect) load(cmd_trace_rays_indirect, "vkCmdTraceRaysIndirectKHR");
  }

  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = caps.queue_family;
  VkCommandPool pool;
  check(vkCreateCommandPool(device_, &pool_info, nullptr, &pool), "vkCreateCommandPool");
  command_pool_ = UniqueCommandPool(device_, pool);
}

Device::~Device() {
  if (device_ != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(device_);
    command_pool_.reset();
    vkDestroyDevice(device_, nullptr);
  }
}

uint32_t Device::memory_type(uint32_t type_bits, VkMemoryPropertyFlags flags) const {
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((type_bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  throw VulkanError("memory type selection (no type with the requested properties)", VK_ERROR_OUT_OF_DEVICE_MEMORY);
}

VkFormatProperties Device::format_properties(VkFormat format) const {
  VkFormatProperties props;
  vkGetPhysicalDeviceFormatProperties(physical_, format, &props);
  return props;
}

void Device::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) const {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = command_pool_.get();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd;
  check(vkAllocateCommandBuffers(device_, &alloc, &cmd), "vkAllocateCommandBuffers");
  struct Free {
    VkDevice d; VkCommandPool p; VkCommandBuffer c;
    ~Free() { vkFreeCommandBuffers(d, p, 1, &c); }
  } free_on_exit{device_, command_pool_.get(), cmd};

  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  record(cmd);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence_handle;
  check(vkCreateFence(device_, &fence_info, nullptr, &fence_handle), "vkCreateFence");
  UniqueFence fence(device_, fence_handle);
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  check(vkQueueSubmit(queue_, 1, &submit, fence.get()), "vkQueueSubmit");
  check(vkWaitForFences(device_, 1, fence.ptr(), VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

void Device::wait_idle() const { check(vkDeviceWaitIdle(device_), "vkDeviceWaitIdle"); }

}  // namespace prismoid::vk
