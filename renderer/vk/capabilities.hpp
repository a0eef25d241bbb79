#pragma once
// What each physical device offers, and what each Prismoid mode needs from it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

namespace prismoid::vk {

struct DeviceCapabilities {
  uint32_t index = 0;  // position in vkEnumeratePhysicalDevices, what `--device N` names
  std::string name;
  std::string type;  // "discrete GPU", "integrated GPU", "CPU", ...
  std::string driver_name;
  std::string driver_info;
  uint32_t api_version = 0;
  bool api_1_3 = false;
  bool mesh_shader = false;
  bool task_shader = false;
  bool ray_tracing_pipeline = false;
  bool acceleration_structure = false;
  bool ray_query = false;
  bool buffer_device_address = false;  // Vulkan 1.2 bufferDeviceAddress (acceleration structures need it)
  // Ray-tracing pipeline properties (zero without VK_KHR_ray_tracing_pipeline): a shader binding
  // table is laid out from these, never from constants (lavapipe: 32/16/32, NVIDIA: 32/32/64).
  uint32_t shader_group_handle_size = 0;
  uint32_t shader_group_handle_alignment = 0;
  uint32_t shader_group_base_alignment = 0;
  uint32_t max_shader_group_stride = 0;
  uint32_t max_ray_recursion_depth = 0;
  uint32_t max_ray_dispatch_invocations = 0;
  bool trace_rays_indirect = false;  // rayTracingPipelineTraceRaysIndirect: launch sizes read from a GPU buffer
  uint32_t min_acceleration_structure_scratch_alignment = 0;  // VK_KHR_acceleration_structure
  // Ray-tracing pipelines, acceleration structures and buffer device addresses together: what
  // Device enables, and what renderer/rt needs. Ray queries are neither needed nor enabled.
  bool ray_tracing() const { return ray_tracing_pipeline && acceleration_structure && buffer_device_address; }
  bool timestamps = false;  // graphics+compute queue with valid timestamp bits
  double timestamp_period_ns = 0.0;
  bool pipeline_statistics = false;  // counts of fragment-shader invocations and primitives
  bool geometry_shader = false;  // the feature fragment shaders need to read gl_PrimitiveID (surface shading)
  bool fragment_stores = false;  // fragmentStoresAndAtomics: fragment shaders may write storage images (counters)
  uint32_t max_image_dimension_2d = 0;  // the widest 2D image (FastAtlas's atlas side)
  bool swapchain = false;
  uint32_t max_mesh_output_vertices = 0;
  uint32_t max_mesh_output_primitives = 0;
  // The most mesh workgroups one draw may launch along x, and in all (lavapipe: 65536 and 2^22):
  // a larger mesh is drawn in several draws (IntervalShadingPass).
  uint32_t max_mesh_groups_x = 0;
  uint32_t max_mesh_groups_total = 0;
  uint32_t subpixel_precision_bits = 0;  // the rasterizer snaps vertices to 2^-bits pixel
  uint64_t max_storage_buffer_range = 0;  // the largest storage buffer one descriptor may name (bytes)
  uint64_t device_local_bytes = 0;
  VkPhysicalDeviceType device_type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t queue_family = UINT32_MAX;  // a family with graphics and compute
};

// Every feature a mode can need; `required` lists them per mode.
enum class Feature { MeshShader, RayTracingPipeline, AccelerationStructure, RayQuery, Timestamps };
const char* feature_name(Feature f);
bool has_feature(const DeviceCapabilities& caps, Feature f);

struct ModeRequirements {
  std::string mode;
  std::vector<Feature> required;
  std::vector<Feature> optional;
  std::string note;
};
// The table `prismoid devices` prints: what volumes, surfaces and GI need.
const std::vector<ModeRequirements>& mode_requirements();

std::vector<DeviceCapabilities> query_devices(VkInstance instance);

// Prefers discrete GPUs, then integrated, virtual and CPU devices (lavapipe), among those
// that offer Vulkan 1.3, mesh shaders and a graphics queue. `forced` picks by index.
// Throws NoSuitableDevice with the reason when nothing fits.
const DeviceCapabilities& select_device(const std::vector<DeviceCapabilities>& devices,
                                        std::optional<uint32_t> forced);

std::string version_string(uint32_t api_version);

}  // namespace prismoid::vk
