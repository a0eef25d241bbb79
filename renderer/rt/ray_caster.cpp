#include "renderer/rt/ray_caster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "scene/input_error.hpp"
#include "shaders/shared/rt.h"

namespace prismoid::rt {

static_assert(sizeof(gpu::RayCastPush) == 80);
static_assert(sizeof(gpu::RayHitRecord) == 32);
static_assert(sizeof(gpu::ShadowRayRecord) == 32);

namespace {

constexpr VkShaderStageFlags kRaygen = VK_SHADER_STAGE_RAYGEN_BIT_KHR;
constexpr std::array<vk::DescriptorBinding, 4> kBindings = {{
    {PRISMOID_RT_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, kRaygen},
    {PRISMOID_RT_BINDING_HITS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kRaygen},
    {PRISMOID_RT_BINDING_SHADOW_RAYS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kRaygen},
    {PRISMOID_RT_BINDING_VISIBILITY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kRaygen},
}};

vk::UniqueDescriptorSetLayout make_set_layout(const vk::Device& device) {
  if (!device.ray_tracing_enabled())
    throw vk::NoSuitableDevice(device.capabilities().name + " has no ray tracing enabled (the ray caster needs "
                               "VK_KHR_ray_tracing_pipeline and VK_KHR_acceleration_structure)");
  return vk::create_descriptor_set_layout(device, kBindings);
}

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout set) {
  const VkPushConstantRange push{kRaygen, 0, sizeof(gpu::RayCastPush)};
  return vk::create_pipeline_layout(device, std::span(&set, 1), std::span(&push, 1));
}

RayTracingPipelineDesc caster_desc(VkPipelineLayout layout) {
  RayTracingPipelineDesc d;
  d.raygen = {"rt/primary.rgen", "rt/shadow.rgen"};  // PRISMOID_RT_RAYGEN_PRIMARY, _SHADOW
  d.miss = {"rt/primary.rmiss", "rt/shadow.rmiss"};  // PRISMOID_RT_MISS_PRIMARY, _SHADOW
  d.hit_groups = {{"rt/primary.rchit", {}}};
  d.layout = layout;
  return d;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace

RayCaster::RayCaster(const vk::Device& device, const SceneAccel& accel)
    : device_(device),
      accel_(accel),
      set_layout_(make_set_layout(device)),
      layout_(make_layout(device, set_layout_.get())),
      pipeline_(device, caster_desc(layout_.get())) {}

namespace {

// Binds the caster's buffers (null: a stub), traces with `raygen` and makes the shader writes
// visible to the host.
struct Launch {
  uint32_t raygen = 0, width = 0, height = 0;
  gpu::RayCastPush push{};
  VkBuffer hits = VK_NULL_HANDLE, rays = VK_NULL_HANDLE, visibility = VK_NULL_HANDLE;
};

}  // namespace

static void run(const vk::Device& device, const SceneAccel& accel, VkDescriptorSetLayout set_layout, VkPipelineLayout layout,
                const RayTracingPipeline& pipeline, const Launch& launch) {
  const vk::Buffer stub(device, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::DeviceLocal);
  const vk::DescriptorSet set = vk::allocate_descriptor_set(device, set_layout, kBindings);
  write_tlas_descriptor(device, set.set, PRISMOID_RT_BINDING_TLAS, accel.tlas());
  auto bind = [&](uint32_t binding, VkBuffer b) {
    vk::write_buffer_descriptor(device, set.set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, b ? b : stub.get());
  };
  bind(PRISMOID_RT_BINDING_HITS, launch.hits);
  bind(PRISMOID_RT_BINDING_SHADOW_RAYS, launch.rays);
  bind(PRISMOID_RT_BINDING_VISIBILITY, launch.visibility);
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, layout, 0, 1, &set.set, 0, nullptr);
    vkCmdPushConstants(cmd, layout, kRaygen, 0, sizeof(launch.push), &launch.push);
    pipeline.trace(cmd, launch.raygen, launch.width, launch.height);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
}

std::vector<RayHit> RayCaster::primary_hits(const Camera& camera, uint32_t width, uint32_t height) const {
  validate(camera);
  if (width == 0 || height == 0) throw InputError("ray caster", "the image size must be positive");
  // The camera frame of reference::ray_direction, in double, then rounded.
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const double tan_half = std::tan(glm::radians(camera.fovy_degrees) * 0.5);
  const double aspect = double(width) / double(height);
  Launch launch;
  launch.raygen = PRISMOID_RT_RAYGEN_PRIMARY;
  launch.width = width;
  launch.height = height;
  launch.push.eye = glm::vec4(accel_.to_local(camera.eye), float(camera.near_distance));
  launch.push.forward = glm::vec4(glm::vec3(forward), 0.0f);
  launch.push.right = glm::vec4(glm::vec3(right * (tan_half * aspect)), 0.0f);
  launch.push.up = glm::vec4(glm::vec3(up * tan_half), 0.0f);
  launch.push.size = glm::uvec4(width, height, 0u, 0u);
  const size_t pixels = size_t(width) * height;
  const vk::Buffer hits(device_, pixels * sizeof(gpu::RayHitRecord), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::HostVisible);
  launch.hits = hits.get();
  run(device_, accel_, set_layout_.get(), layout_.get(), pipeline_, launch);

  std::vector<RayHit> out(pixels);
  std::vector<gpu::RayHitRecord> records(pixels);
  std::memcpy(records.data(), hits.mapped(), pixels * sizeof(gpu::RayHitRecord));
  for (size_t i = 0; i < pixels; ++i) {
    const gpu::RayHitRecord& r = records[i];
    out[i].hit = r.id.z != 0;
    out[i].t = r.hit.x;
    out[i].b1 = r.hit.y;
    out[i].b2 = r.hit.z;
    out[i].mesh = r.id.x;
    out[i].triangle = r.id.y;
  }
  return out;
}

std::vector<uint8_t> RayCaster::visibility(std::span<const ShadowSegment> segments) const {
  std::vector<uint8_t> out(segments.size(), 1);
  std::vector<gpu::ShadowRayRecord> records;
  std::vector<size_t> traced;  // segment index per record
  for (size_t i = 0; i < segments.size(); ++i) {
    const ShadowSegment& s = segments[i];
    if (!finite(s.from) || !finite(s.to) || !std::isfinite(s.s_min) || !std::isfinite(s.s_max))
      throw InputError("shadow rays", "segment " + std::to_string(i) + " is not finite");
    if (!(s.s_min >= 0.0 && s.s_max >= s.s_min))
      throw InputError("shadow rays", "segment " + std::to_string(i) + " needs 0 <= s_min <= s_max");
    const glm::vec3 direction(s.to - s.from);
    if (direction == glm::vec3(0.0f)) continue;  // a point: nothing lies on it
    gpu::ShadowRayRecord r;
    r.origin = glm::vec4(accel_.to_local(s.from), float(s.s_min));
    r.direction = glm::vec4(direction, float(s.s_max));
    records.push_back(r);
    traced.push_back(i);
  }
  if (records.empty()) return out;
  const auto count = static_cast<uint32_t>(records.size());
  const vk::Buffer rays(device_, records.size() * sizeof(gpu::ShadowRayRecord), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        vk::MemoryUse::HostVisible);
  std::memcpy(rays.mapped(), records.data(), records.size() * sizeof(gpu::ShadowRayRecord));
  const vk::Buffer visible(device_, records.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::HostVisible);
  Launch launch;
  launch.raygen = PRISMOID_RT_RAYGEN_SHADOW;
  launch.width = std::min<uint32_t>(count, 8192);
  launch.height = (count + launch.width - 1) / launch.width;
  launch.push.size = glm::uvec4(0u, 0u, count, launch.width);
  launch.rays = rays.get();
  launch.visibility = visible.get();
  run(device_, accel_, set_layout_.get(), layout_.get(), pipeline_, launch);
  std::vector<uint32_t> flags(records.size());
  std::memcpy(flags.data(), visible.mapped(), flags.size() * sizeof(uint32_t));
  for (size_t k = 0; k < traced.size(); ++k) out[traced[k]] = flags[k] != 0 ? 1 : 0;
  return out;
}

std::vector<uint8_t> RayCaster::point_light_visibility(std::span<const glm::dvec3> points, const glm::dvec3& light,
                                                       double spawn) const {
  if (!(spawn >= 0.0) || !std::isfinite(spawn)) throw InputError("shadow rays", "the spawn distance must be finite and >= 0");
  std::vector<ShadowSegment> segments(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const double length = glm::length(light - points[i]);
    segments[i].from = points[i];
    segments[i].to = light;
    if (length > 2.0 * spawn) {
      segments[i].s_min = spawn / length;
      segments[i].s_max = 1.0 - spawn / length;
    } else {
      segments[i].s_min = segments[i].s_max = 0.5;  // closer than the skipped ends: nothing left to block
      segments[i].to = points[i];
    }
  }
  return visibility(segments);
}

}  // namespace prismoid::rt
