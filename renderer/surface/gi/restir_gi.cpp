#include "renderer/surface/gi/restir_gi.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

constexpr VkShaderStageFlags kStages =
    VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR | VK_SHADER_STAGE_MISS_BIT_KHR;
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
constexpr VkBufferUsageFlags kReservoirUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
constexpr uint32_t kLaunchWidth = 1024;
constexpr uint32_t kMaxNeighbours = 16;  // PRISMOID_GI_MAX_NEIGHBOURS in spatial.glsl

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout set) {
  const VkPushConstantRange push{VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof(gpu::GiSettings)};
  return vk::create_pipeline_layout(device, std::span(&set, 1), std::span(&push, 1));
}

rt::RayTracingPipelineDesc pipeline_desc(VkPipelineLayout layout) {
  return surface_rt_pipeline({"surface/gi/dense_initial.rgen", "surface/gi/dense_spatial.rgen"}, layout);
}

// The frame block GI shades with: the scene's lights and sky; the sky reaches samples through
// GI (sky_up.w = 1: no ambient term). No camera: each sample carries its viewer direction.
gpu::SurfaceFrame gi_frame(const GpuSurfaceScene& scene) {
  gpu::SurfaceFrame f{};
  f.view = glm::mat4(1.0f);
  f.projection = glm::mat4(1.0f);
  f.viewport = glm::vec4(1.0f);
  f.counts = glm::uvec4(scene.point_light_count, scene.directional_light_count, scene.emitter_count, scene.sky.black() ? 0u : 1u);
  f.sky_top = glm::vec4(glm::vec3(scene.sky.top), 0.0f);
  f.sky_bottom = glm::vec4(glm::vec3(scene.sky.bottom), 0.0f);
  f.sky_up = glm::vec4(glm::vec3(glm::normalize(scene.sky.up)), 1.0f);
  return f;
}

template <typename T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span(v));
}

}  // namespace

std::vector<vk::DescriptorBinding> gi_bindings() {
  std::vector<vk::DescriptorBinding> b = scene_bindings({.stages = kStages, .vertex_buffers = true, .tlas = true});
  for (uint32_t binding : {PRISMOID_GI_BINDING_SAMPLES, PRISMOID_GI_BINDING_SLOTS, PRISMOID_GI_BINDING_TEMPORAL,
                           PRISMOID_GI_BINDING_FALLBACK, PRISMOID_GI_BINDING_OUTPUT, PRISMOID_GI_BINDING_DIRECT,
                           PRISMOID_GI_BINDING_HOST, PRISMOID_GI_BINDING_HOST + 1})
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  return b;
}

vk::UniqueDescriptorSetLayout gi_set_layout(const vk::Device& device) {
  if (!device.ray_tracing_enabled())
    throw vk::NoSuitableDevice(device.capabilities().name + " has no ray tracing enabled (ReSTIR GI traces its rays)");
  return vk::create_descriptor_set_layout(device, gi_bindings());
}


RestirGiPipeline::RestirGiPipeline(const vk::Device& device)
    : set_layout_(gi_set_layout(device)),
      layout_(make_layout(device, set_layout_.get())),
      pipeline_(device, pipeline_desc(layout_.get())) {}

RestirGi::RestirGi(const vk::Device& device, const GpuSurfaceScene& scene, const rt::SceneAccel& accel, const GiDenseSet& set)
    : RestirGi(device, std::make_unique<RestirGiPipeline>(device), nullptr, scene, accel, set) {}

RestirGi::RestirGi(const vk::Device& device, const RestirGiPipeline& pipeline, const GpuSurfaceScene& scene, const rt::SceneAccel& accel,
                   const GiDenseSet& set)
    : RestirGi(device, nullptr, &pipeline, scene, accel, set) {}

RestirGi::RestirGi(const vk::Device& device, std::unique_ptr<RestirGiPipeline> owned, const RestirGiPipeline* shared,
                   const GpuSurfaceScene& scene, const rt::SceneAccel& accel, const GiDenseSet& set)
    : device_(device), own_pipeline_(std::move(owned)), pipeline_(shared ? *shared : *own_pipeline_) {
  if (set.samples.empty()) throw InputError("ReSTIR GI", "the sample set is empty");
  if (glm::length(scene.origin - accel.origin()) != 0.0)
    throw InputError("ReSTIR GI", "the scene's GPU buffers and its acceleration structure use different origins");
  count_ = static_cast<uint32_t>(set.samples.size());

  std::vector<gpu::GiSample> samples(count_);
  for (uint32_t i = 0; i < count_; ++i) {
    const GiDenseSample& s = set.samples[i];
    samples[i].position = glm::vec4(glm::vec3(s.position - scene.origin), float(s.bary.y));
    samples[i].viewer = glm::vec4(glm::vec3(s.viewer), float(s.bary.z));
    samples[i].id = glm::uvec4(s.global_triangle, 0u, 0u, 0u);
  }
  samples_ = vk::upload_buffer(device, bytes_of(samples), kStorage);
  const VkDeviceSize reservoirs = VkDeviceSize(count_) * sizeof(gpu::GiReservoir);
  slots_ = vk::Buffer(device, reservoirs, kReservoirUsage, vk::MemoryUse::DeviceLocal);
  temporal_ = vk::Buffer(device, reservoirs, kReservoirUsage, vk::MemoryUse::DeviceLocal);
  fallback_ = vk::Buffer(device, reservoirs, kReservoirUsage, vk::MemoryUse::DeviceLocal);
  output_ = vk::Buffer(device, VkDeviceSize(count_) * 16, kReservoirUsage, vk::MemoryUse::DeviceLocal);
  direct_ = vk::Buffer(device, VkDeviceSize(count_) * 16, kReservoirUsage, vk::MemoryUse::DeviceLocal);
  history_ = vk::Buffer(device, VkDeviceSize(count_) * sizeof(uint32_t), kStorage, vk::MemoryUse::HostVisible);
  history_valid_.assign(count_, 0u);
  // A header of four words, then the neighbours (at least one entry: an empty buffer is invalid).
  std::vector<uint32_t> table = {set.table_width, set.max_radius, 0u, 0u};
  table.insert(table.end(), set.neighbours.begin(), set.neighbours.end());
  if (set.neighbours.empty()) table.push_back(kNoNeighbour);
  neighbours_ = vk::upload_buffer(device, bytes_of(table), kStorage);
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  const gpu::SurfaceFrame frame = gi_frame(scene);
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));

  const std::vector<vk::DescriptorBinding> bindings = gi_bindings();
  set_ = vk::allocate_descriptor_set(device, pipeline_.set_layout(), bindings);
  write_scene_descriptors(device, set_.set, scene, true);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                              frame_uniforms_.get());
  rt::write_tlas_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_TLAS, accel.tlas());
  const std::pair<uint32_t, VkBuffer> own[] = {
      {PRISMOID_GI_BINDING_SAMPLES, samples_.get()},   {PRISMOID_GI_BINDING_SLOTS, slots_.get()},
      {PRISMOID_GI_BINDING_TEMPORAL, temporal_.get()}, {PRISMOID_GI_BINDING_FALLBACK, fallback_.get()},
      {PRISMOID_GI_BINDING_OUTPUT, output_.get()},     {PRISMOID_GI_BINDING_DIRECT, direct_.get()},
      {PRISMOID_GI_BINDING_HOST, history_.get()},      {PRISMOID_GI_BINDING_HOST + 1, neighbours_.get()},
  };
  for (const auto& [binding, buffer] : own)
    vk::write_buffer_descriptor(device, set_.set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer);
}

void RestirGi::invalidate_history(std::span<const uint32_t> samples) {
  for (uint32_t s : samples) {
    if (s >= count_) throw InputError("ReSTIR GI", "sample " + std::to_string(s) + " is not in the sample set");
    history_valid_[s] = 0u;
  }
}

void RestirGi::reset() {
  std::fill(history_valid_.begin(), history_valid_.end(), 0u);
  clear_ = true;
}

void RestirGi::record(VkCommandBuffer cmd, uint32_t frame_index, const RestirGiSettings& s, vk::GpuTimer* timer) {
  if (s.spatial_neighbours > kMaxNeighbours)
    throw InputError("ReSTIR GI", "at most " + std::to_string(kMaxNeighbours) + " spatial neighbours");
  if (!(s.m_cap >= 0.0) || !std::isfinite(s.m_cap) || !(s.radius >= 0.0) || !std::isfinite(s.radius))
    throw InputError("ReSTIR GI", "the M cap and the radius must be finite and >= 0");
  if (!(s.jacobian_limit >= 1.0)) throw InputError("ReSTIR GI", "the Jacobian limit must be at least 1");
  std::memcpy(history_.mapped(), history_valid_.data(), history_valid_.size() * sizeof(uint32_t));
  std::fill(history_valid_.begin(), history_valid_.end(), 1u);  // this frame writes every slot

  gpu::GiSettings push{};
  uint32_t flags = 0;
  if (s.unbiased) flags |= PRISMOID_GI_UNBIASED;
  if (s.fallback) flags |= PRISMOID_GI_FALLBACK;
  if (s.temporal) flags |= PRISMOID_GI_TEMPORAL;
  if (!s.new_candidates) flags |= PRISMOID_GI_NO_INITIAL;
  if (s.write_direct) flags |= PRISMOID_GI_WRITE_DIRECT;
  push.params = glm::uvec4(frame_index, count_, flags, s.spatial_neighbours);
  push.limits = glm::vec4(float(s.m_cap), float(s.radius), float(std::cos(glm::radians(s.max_normal_angle_degrees))),
                          float(s.jacobian_limit));

  if (clear_) {
    for (const vk::Buffer* b : {&slots_, &temporal_, &fallback_, &output_, &direct_}) vkCmdFillBuffer(cmd, b->get(), 0, VK_WHOLE_SIZE, 0);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    clear_ = false;
  }
  // The previous frame's passes (or readback copies) are done with the buffers.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline_.pipeline().get());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline_.layout(), 0, 1, &set_.set, 0, nullptr);
  vkCmdPushConstants(cmd, pipeline_.layout(), VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof(push), &push);
  const uint32_t width = std::min(count_, kLaunchWidth), height = (count_ + width - 1) / width;
  {
    std::optional<vk::ScopedPass> pass;
    if (timer) pass.emplace(*timer, cmd, "gi initial+temporal");
    pipeline_.pipeline().trace(cmd, PRISMOID_GI_RAYGEN_INITIAL, width, height);
  }
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  {
    std::optional<vk::ScopedPass> pass;
    if (timer) pass.emplace(*timer, cmd, "gi spatial");
    pipeline_.pipeline().trace(cmd, PRISMOID_GI_RAYGEN_SPATIAL, width, height);
  }
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_TRANSFER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                     VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

std::vector<std::byte> RestirGi::read(const vk::Buffer& buffer) const {
  const vk::Buffer staging(device_, buffer.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    const VkBufferCopy region{0, 0, buffer.size()};
    vkCmdCopyBuffer(cmd, buffer.get(), staging.get(), 1, &region);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                       VK_ACCESS_2_HOST_READ_BIT);
  });
  std::vector<std::byte> out(buffer.size());
  std::memcpy(out.data(), staging.mapped(), out.size());
  return out;
}

namespace {
std::vector<glm::vec3> rgb_of(const std::vector<std::byte>& bytes) {
  std::vector<glm::vec4> v(bytes.size() / sizeof(glm::vec4));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(glm::vec4));
  std::vector<glm::vec3> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = glm::vec3(v[i]);
  return out;
}
std::vector<gpu::GiReservoir> reservoirs_of(const std::vector<std::byte>& bytes) {
  std::vector<gpu::GiReservoir> v(bytes.size() / sizeof(gpu::GiReservoir));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(gpu::GiReservoir));
  return v;
}
}  // namespace

std::vector<glm::vec3> RestirGi::read_indirect() const { return rgb_of(read(output_)); }
std::vector<glm::vec3> RestirGi::read_direct() const { return rgb_of(read(direct_)); }
std::vector<gpu::GiReservoir> RestirGi::read_reservoirs() const { return reservoirs_of(read(slots_)); }
std::vector<gpu::GiReservoir> RestirGi::read_temporal() const { return reservoirs_of(read(temporal_)); }
std::vector<gpu::GiReservoir> RestirGi::read_fallback() const { return reservoirs_of(read(fallback_)); }

}  // namespace prismoid::surface
