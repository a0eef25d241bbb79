#include "renderer/vk/capabilities.hpp"

#include <algorithm>
#include <cstring>

#include "renderer/vk/error.hpp"
#include "scene/setting_names.hpp"

namespace prismoid::vk {

const char* feature_name(Feature f) {
  switch (f) {
    case Feature::MeshShader: return "mesh shader (VK_EXT_mesh_shader)";
    case Feature::RayTracingPipeline: return "ray-tracing pipeline (VK_KHR_ray_tracing_pipeline)";
    case Feature::AccelerationStructure: return "acceleration structures (VK_KHR_acceleration_structure)";
    case Feature::RayQuery: return "ray query (VK_KHR_ray_query)";
    case Feature::Timestamps: return "GPU timestamps";
  }
  return "?";
}

bool has_feature(const DeviceCapabilities& caps, Feature f) {
  switch (f) {
    case Feature::MeshShader: return caps.mesh_shader;
    case Feature::RayTracingPipeline: return caps.ray_tracing_pipeline;
    case Feature::AccelerationStructure: return caps.acceleration_structure;
    case Feature::RayQuery: return caps.ray_query;
    case Feature::Timestamps: return caps.timestamps;
  }
  return false;
}

const std::vector<ModeRequirements>& mode_requirements() {
  static const std::vector<ModeRequirements> table = {
      {"volume: interval shading", {Feature::MeshShader}, {Feature::Timestamps}, "one mesh-shader workgroup emits tetrahedron proxies"},
      {"surface: forward, htex, meshlet atlas, texel, fastatlas", {}, {Feature::MeshShader, Feature::Timestamps}, "rasterization and compute"},
      {"surface GI: ReSTIR GI", {Feature::RayTracingPipeline, Feature::AccelerationStructure}, {Feature::RayQuery},
       "rays traced with ray-tracing pipelines; ray queries used only where present"},
  };
  return table;
}

std::string version_string(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

namespace {

const char* type_name(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

int type_rank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

bool has_extension(const std::vector<VkExtensionProperties>& list, const char* name) {
  return std::any_of(list.begin(), list.end(), [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

DeviceCapabilities describe(VkPhysicalDevice device, uint32_t index) {
  DeviceCapabilities caps;
  caps.index = index;

  uint32_t ext_count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &ext_count, nullptr);
  std::vector<VkExtensionProperties> extensions(ext_count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &ext_count, extensions.data());
  bool ext_mesh = has_extension(extensions, VK_EXT_MESH_SHADER_EXTENSION_NAME);
  bool ext_rt = has_extension(extensions, VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
  bool ext_as = has_extension(extensions, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) &&
                has_extension(extensions, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
  bool ext_rq = has_extension(extensions, VK_KHR_RAY_QUERY_EXTENSION_NAME);
  caps.swapchain = has_extension(extensions, VK_KHR_SWAPCHAIN_EXTENSION_NAME);

  VkPhysicalDeviceMeshShaderFeaturesEXT mesh{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT};
  VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  VkPhysicalDeviceRayQueryFeaturesKHR rq{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceVulkan12Features v12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  VkPhysicalDeviceProperties basic;
  vkGetPhysicalDeviceProperties(device, &basic);
  const bool api_1_2 = VK_API_VERSION_MAJOR(basic.apiVersion) > 1 || VK_API_VERSION_MINOR(basic.apiVersion) >= 2;
  // Chain only the structures of extensions (and core versions) the device has.
  void** next = &features.pNext;
  auto chain = [&next](auto& s) { *next = &s; next = &s.pNext; };
  if (api_1_2) chain(v12);
  if (ext_mesh) chain(mesh);
  if (ext_rt) chain(rt);
  if (ext_as) chain(as);
  if (ext_rq) chain(rq);
  vkGetPhysicalDeviceFeatures2(device, &features);

  VkPhysicalDeviceMeshShaderPropertiesEXT mesh_props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_PROPERTIES_EXT};
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceRayTracingPipelinePropertiesKHR rt_props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR};
  VkPhysicalDeviceAccelerationStructurePropertiesKHR as_props{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  next = &props.pNext;
  chain(driver);
  if (ext_mesh) chain(mesh_props);
  if (ext_rt) chain(rt_props);
  if (ext_as) chain(as_props);
  vkGetPhysicalDeviceProperties2(device, &props);

  caps.name = props.properties.deviceName;
  caps.device_type = props.properties.deviceType;
  caps.type = type_name(props.properties.deviceType);
  caps.driver_name = driver.driverName;
  caps.driver_info = driver.driverInfo;
  caps.api_version = props.properties.apiVersion;
  caps.api_1_3 = VK_API_VERSION_MAJOR(caps.api_version) > 1 || VK_API_VERSION_MINOR(caps.api_version) >= 3;
  caps.mesh_shader = ext_mesh && mesh.meshShader;
  caps.task_shader = ext_mesh && mesh.taskShader;
  caps.ray_tracing_pipeline = ext_rt && rt.rayTracingPipeline;
  caps.trace_rays_indirect = caps.ray_tracing_pipeline && rt.rayTracingPipelineTraceRaysIndirect;
  caps.acceleration_structure = ext_as && as.accelerationStructure;
  caps.ray_query = ext_rq && rq.rayQuery;
  caps.buffer_device_address = api_1_2 && v12.bufferDeviceAddress;
  if (ext_rt) {
    caps.shader_group_handle_size = rt_props.shaderGroupHandleSize;
    caps.shader_group_handle_alignment = rt_props.shaderGroupHandleAlignment;
    caps.shader_group_base_alignment = rt_props.shaderGroupBaseAlignment;
    caps.max_shader_group_stride = rt_props.maxShaderGroupStride;
    caps.max_ray_recursion_depth = rt_props.maxRayRecursionDepth;
    caps.max_ray_dispatch_invocations = rt_props.maxRayDispatchInvocationCount;
  }
  if (ext_as) caps.min_acceleration_structure_scratch_alignment = as_props.minAccelerationStructureScratchOffsetAlignment;
  caps.timestamp_period_ns = props.properties.limits.timestampPeriod;
  caps.pipeline_statistics = features.features.pipelineStatisticsQuery == VK_TRUE;
  caps.geometry_shader = features.features.geometryShader == VK_TRUE;
  caps.fragment_stores = features.features.fragmentStoresAndAtomics == VK_TRUE;
  caps.max_image_dimension_2d = props.properties.limits.maxImageDimension2D;
  caps.subpixel_precision_bits = props.properties.limits.subPixelPrecisionBits;
  caps.max_storage_buffer_range = props.properties.limits.maxStorageBufferRange;
  if (ext_mesh) {
    caps.max_mesh_output_vertices = mesh_props.maxMeshOutputVertices;
    caps.max_mesh_output_primitives = mesh_props.maxMeshOutputPrimitives;
    caps.max_mesh_groups_x = mesh_props.maxMeshWorkGroupCount[0];
    caps.max_mesh_groups_total = mesh_props.maxMeshWorkGroupTotalCount;
  }

  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(device, &family_count, families.data());
  for (uint32_t i = 0; i < family_count; ++i) {
    VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & need) == need) {
      caps.queue_family = i;
      caps.timestamps = families[i].timestampValidBits > 0 && caps.timestamp_period_ns > 0.0;
      break;
    }
  }

  VkPhysicalDeviceMemoryProperties memory;
  vkGetPhysicalDeviceMemoryProperties(device, &memory);
  for (uint32_t i = 0; i < memory.memoryHeapCount; ++i)
    if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) caps.device_local_bytes += memory.memoryHeaps[i].size;
  return caps;
}

std::string unsuitable_reason(const DeviceCapabilities& d) {
  if (!d.api_1_3) return "offers Vulkan " + version_string(d.api_version) + ", Prismoid needs 1.3";
  if (d.queue_family == UINT32_MAX) return "has no queue with graphics and compute";
  if (!d.mesh_shader) return "has no mesh shaders (VK_EXT_mesh_shader); on Debian 12 install mesa-vulkan-drivers from bookworm-backports";
  return {};
}

}  // namespace

std::vector<DeviceCapabilities> query_devices(VkInstance instance) {
  uint32_t count = 0;
  check(vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  check(vkEnumeratePhysicalDevices(instance, &count, devices.data()), "vkEnumeratePhysicalDevices");
  std::vector<DeviceCapabilities> result;
  for (uint32_t i = 0; i < count; ++i) result.push_back(describe(devices[i], i));
  return result;
}

const DeviceCapabilities& select_device(const std::vector<DeviceCapabilities>& devices, std::optional<uint32_t> forced) {
  if (devices.empty()) throw NoSuitableDevice("no Vulkan device found (is mesa-vulkan-drivers installed?)");
  if (forced) {
    if (*forced >= devices.size())
      throw NoSuitableDevice(setting("device", std::to_string(*forced)) + " does not exist: there are " +
                             std::to_string(devices.size()) + " devices (see `prismoid devices`)");
    const auto& d = devices[*forced];
    if (auto why = unsuitable_reason(d); !why.empty()) throw NoSuitableDevice("device " + std::to_string(d.index) + " (" + d.name + ") " + why);
    return d;
  }
  const DeviceCapabilities* best = nullptr;
  std::string reasons;
  for (const auto& d : devices) {
    if (auto why = unsuitable_reason(d); !why.empty()) {
      reasons += "\n  device " + std::to_string(d.index) + " (" + d.name + ") " + why;
      continue;
    }
    if (!best || type_rank(d.device_type) < type_rank(best->device_type)) best = &d;
  }
  if (!best) throw NoSuitableDevice("no Vulkan device can render volumes:" + reasons);
  return *best;
}

}  // namespace prismoid::vk
