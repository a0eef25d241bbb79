#include "renderer/surface/gi/htex_gi.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>

#include <glm/trigonometric.hpp>

#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/surface/surface_frame.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/gi.h"
#include "shaders/shared/htex.h"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

constexpr VkBufferUsageFlags kBufferUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
constexpr uint32_t kMaxNeighbours = 16;     // PRISMOID_GI_MAX_NEIGHBOURS in spatial.glsl
constexpr uint32_t kHostNoSnap = 256u;      // PRISMOID_GI_HTEX_NO_SNAP in htex_host_common.glsl
constexpr uint32_t kRaygenSamples = 0, kRaygenInitial = 1, kRaygenSpatial = 2;

std::vector<vk::DescriptorBinding> htex_bindings() {
  std::vector<vk::DescriptorBinding> b = htex_table_bindings(VK_SHADER_STAGE_RAYGEN_BIT_KHR);
  for (uint32_t binding : {PRISMOID_HTEX_BINDING_OCCUPANCY, PRISMOID_HTEX_BINDING_PAGE_TABLE, PRISMOID_HTEX_BINDING_TASKS})
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  return b;
}

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout gi, VkDescriptorSetLayout htex) {
  const VkDescriptorSetLayout sets[] = {gi, htex};
  const VkPushConstantRange push{VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof(gpu::GiSettings)};
  return vk::create_pipeline_layout(device, std::span(sets), std::span(&push, 1));
}

rt::RayTracingPipelineDesc pipeline_desc(VkPipelineLayout layout) {
  return surface_rt_pipeline({"surface/gi/htex_samples.rgen", "surface/gi/htex_initial.rgen", "surface/gi/htex_spatial.rgen"}, layout);
}

void rt_barrier(VkCommandBuffer cmd) {
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

}  // namespace

HtexGi::HtexGi(const vk::Device& device, const HtexPass& pass, const GpuSurfaceScene& scene, const rt::SceneAccel& accel,
               const HtexGiOptions& options)
    : device_(device),
      pass_(pass),
      scene_(scene),
      gi_layout_(gi_set_layout(device)),
      htex_layout_(vk::create_descriptor_set_layout(device, htex_bindings())),
      layout_(make_layout(device, gi_layout_.get(), htex_layout_.get())),
      pipeline_(device, pipeline_desc(layout_.get())) {
  if (!pass.settings().indirect) throw std::invalid_argument("HtexGi: the Htex pass needs HtexSettings::indirect (GI's output buffer)");
  if (glm::length(scene.origin - accel.origin()) != 0.0)
    throw InputError("ReSTIR GI", "the scene's GPU buffers and its acceleration structure use different origins");
  const uint64_t texels = uint64_t(pass.settings().pool_pages) * PRISMOID_HTEX_PAGE_TEXELS;
  const uint64_t range = device.capabilities().max_storage_buffer_range;
  if (texels * sizeof(gpu::GiReservoir) > range)
    throw InputError(setting("pool-pages"), std::to_string(pass.settings().pool_pages) + " pages need " +
                                         std::to_string(texels * sizeof(gpu::GiReservoir)) + "-byte GI reservoir buffers, beyond the " +
                                         std::to_string(range) + "-byte storage-buffer range of " + device.capabilities().name);

  // The persistent layer: per mesh the finest level whose texels fit the mesh's share.
  const HtexGeometry& g = pass.geometry();
  const auto& meshes = g.layout.meshes();
  const uint64_t share = std::max<uint64_t>(1, options.persistent_texel_budget / std::max<size_t>(1, meshes.size()));
  std::vector<glm::uvec4> layers(std::max<size_t>(1, meshes.size()), glm::uvec4(0u));
  for (size_t m = 0; m < meshes.size(); ++m) {
    const htex::MeshLayout& ml = meshes[m];
    uint32_t level = ml.levels - 1;
    for (uint32_t l = 0; l < ml.levels; ++l)
      if (uint64_t(ml.quad_count) * ml.side(l) * ml.side(l) <= share) {
        level = l;
        break;
      }
    const uint32_t side = ml.side(level);
    layers[m] = glm::uvec4(uint32_t(persistent_texels_), level, side, 0u);
    persistent_levels_.push_back(level);
    persistent_texels_ += uint64_t(ml.quad_count) * side * side;
  }
  if (persistent_texels_ * sizeof(gpu::GiReservoir) > range)
    throw InputError("ReSTIR GI", "the fallback layer (" + std::to_string(persistent_texels_) + " texels) exceeds the storage-buffer range");

  samples_ = vk::Buffer(device, texels * sizeof(gpu::GiSample), kBufferUsage, vk::MemoryUse::DeviceLocal);
  slots_ = vk::Buffer(device, texels * sizeof(gpu::GiReservoir), kBufferUsage, vk::MemoryUse::DeviceLocal);
  temporal_ = vk::Buffer(device, texels * sizeof(gpu::GiReservoir), kBufferUsage, vk::MemoryUse::DeviceLocal);
  stamps_ = vk::Buffer(device, texels * 16, kBufferUsage, vk::MemoryUse::DeviceLocal);
  fallback_ = vk::Buffer(device, std::max<uint64_t>(1, persistent_texels_) * sizeof(gpu::GiReservoir), kBufferUsage,
                         vk::MemoryUse::DeviceLocal);
  layers_ = vk::upload_buffer(device, std::as_bytes(std::span(layers)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  direct_ = vk::Buffer(device, 16, kBufferUsage, vk::MemoryUse::DeviceLocal);  // PRISMOID_GI_WRITE_DIRECT is never set
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);

  const std::vector<vk::DescriptorBinding> gb = gi_bindings();
  gi_set_ = vk::allocate_descriptor_set(device, gi_layout_.get(), gb);
  write_scene_descriptors(device, gi_set_.set, scene, true);
  vk::write_buffer_descriptor(device, gi_set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  rt::write_tlas_descriptor(device, gi_set_.set, PRISMOID_SURFACE_BINDING_TLAS, accel.tlas());
  const std::pair<uint32_t, VkBuffer> own[] = {
      {PRISMOID_GI_BINDING_SAMPLES, samples_.get()},   {PRISMOID_GI_BINDING_SLOTS, slots_.get()},
      {PRISMOID_GI_BINDING_TEMPORAL, temporal_.get()}, {PRISMOID_GI_BINDING_FALLBACK, fallback_.get()},
      {PRISMOID_GI_BINDING_OUTPUT, pass.indirect_radiance().get()},
      {PRISMOID_GI_BINDING_DIRECT, direct_.get()},     {PRISMOID_GI_BINDING_HOST, stamps_.get()},
      {PRISMOID_GI_BINDING_HOST + 1, layers_.get()},
  };
  for (const auto& [binding, buffer] : own)
    vk::write_buffer_descriptor(device, gi_set_.set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer);
  const std::vector<vk::DescriptorBinding> hb = htex_bindings();
  htex_set_ = vk::allocate_descriptor_set(device, htex_layout_.get(), hb);
  write_htex_table_descriptors(device, htex_set_.set, pass.tables());
  const std::pair<uint32_t, VkBuffer> residency[] = {
      {PRISMOID_HTEX_BINDING_OCCUPANCY, pass.occupancy().get()},
      {PRISMOID_HTEX_BINDING_PAGE_TABLE, pass.page_table().get()},
      {PRISMOID_HTEX_BINDING_TASKS, pass.tasks().get()},
  };
  for (const auto& [binding, buffer] : residency)
    vk::write_buffer_descriptor(device, htex_set_.set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer);
  reset();
}

void HtexGi::reset() {
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    for (const vk::Buffer* b : {&samples_, &slots_, &temporal_, &stamps_, &fallback_, &direct_}) vkCmdFillBuffer(cmd, b->get(), 0, VK_WHOLE_SIZE, 0u);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
}

uint64_t HtexGi::reservoir_bytes() const { return samples_.size() + slots_.size() + temporal_.size() + stamps_.size(); }
uint64_t HtexGi::persistent_bytes() const { return persistent_texels_ * sizeof(gpu::GiReservoir); }

void HtexGi::record(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent, uint32_t frame, const RestirGiSettings& s,
                    vk::GpuTimer* timer) {
  if (s.spatial_neighbours > kMaxNeighbours)
    throw InputError(setting("gi-neighbours"), "at most " + std::to_string(kMaxNeighbours) + " spatial neighbours");
  if (!(s.m_cap >= 0.0) || !std::isfinite(s.m_cap) || !(s.radius >= 0.0) || !std::isfinite(s.radius))
    throw InputError("ReSTIR GI", "the M cap and the radius must be finite and >= 0");
  if (!(s.jacobian_limit >= 1.0)) throw InputError("ReSTIR GI", "the Jacobian limit must be at least 1");
  gpu::SurfaceFrame f = surface_frame(scene_, camera, extent, glm::dvec2(0.0));
  f.sky_up.w = 1.0f;  // GI's bounce rays bring the sky
  frame_uniforms_.write(std::as_bytes(std::span(&f, 1)));

  gpu::GiSettings push{};
  uint32_t flags = 0;
  if (s.unbiased) flags |= PRISMOID_GI_UNBIASED;
  if (s.fallback) flags |= PRISMOID_GI_FALLBACK;
  if (s.temporal) flags |= PRISMOID_GI_TEMPORAL;
  if (!s.new_candidates) flags |= PRISMOID_GI_NO_INITIAL;
  if (!pass_.settings().snap_vertex_corners) flags |= kHostNoSnap;
  const uint64_t texels = uint64_t(pass_.settings().pool_pages) * PRISMOID_HTEX_PAGE_TEXELS;
  push.params = glm::uvec4(frame, uint32_t(texels), flags, s.spatial_neighbours);
  push.limits = glm::vec4(float(s.m_cap), float(s.radius), float(std::cos(glm::radians(s.max_normal_angle_degrees))),
                          float(s.jacobian_limit));

  // The shading pass (and the previous frame's GI) are done; the task list and launch are written.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  const VkDescriptorSet sets[] = {gi_set_.set, htex_set_.set};
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline_.get());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, layout_.get(), 0, 2, sets, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof(push), &push);
  const VkDeviceAddress launch = pass_.state().device_address();  // HtexStateGpu::trace: (8, 8, tasks)
  auto trace = [&](uint32_t raygen, const char* name) {
    std::optional<vk::ScopedPass> scoped;
    if (timer) scoped.emplace(*timer, cmd, name);
    pipeline_.trace_indirect(cmd, raygen, launch);
  };
  trace(kRaygenSamples, "gi samples");
  rt_barrier(cmd);
  trace(kRaygenInitial, "gi initial+temporal");
  rt_barrier(cmd);
  trace(kRaygenSpatial, "gi spatial");
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_COPY_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT);
}

HtexGiImage render_htex_gi(const vk::Device& device, HtexPass& pass, HtexGi& gi, const GpuSurfaceScene& scene,
                           VkAccelerationStructureKHR tlas, const Camera& camera, VkExtent2D extent, uint32_t frames,
                           const RestirGiSettings& settings, uint32_t first_frame, bool keep_frames) {
  if (frames == 0) throw InputError(setting("gi-frames"), "at least one frame");
  HtexTargets targets = create_htex_targets(device, extent);
  vk::GpuTimer timer(device, 8);
  HtexGiImage out;
  HtexImage& image = out.image;
  image.width = extent.width;
  image.height = extent.height;
  const size_t pixels = size_t(extent.width) * extent.height;
  std::vector<double> sum(pixels * 4, 0.0);
  std::vector<float> rgba(pixels * 4);
  for (uint32_t k = 0; k < frames; ++k) {
    device.submit_and_wait([&](VkCommandBuffer cmd) {
      timer.reset(cmd);
      pass.record_marking(cmd, scene, tlas, targets, camera, timer);
      pass.record_allocation(cmd, targets, timer);
      pass.record_shading(cmd, targets, timer);
      gi.record(cmd, camera, extent, first_frame + k, settings, &timer);
      pass.record_gather(cmd, targets, timer);
    });
    vk::read_image(device, targets.color, sizeof(float) * 4, std::as_writable_bytes(std::span(rgba)));
    for (size_t i = 0; i < rgba.size(); ++i) sum[i] += double(rgba[i]);
    if (keep_frames) out.frames.push_back(rgba);
  }
  image.rgba.resize(pixels * 4);
  for (size_t i = 0; i < rgba.size(); ++i) image.rgba[i] = (i % 4 == 3) ? rgba[i] : float(sum[i] / frames);
  const std::vector<std::byte> vis = pass.read_buffer(targets.visibility);
  image.visibility.resize(pixels);
  std::memcpy(image.visibility.data(), vis.data(), pixels * sizeof(glm::uvec4));
  image.passes = timer.read();
  image.counters = pass.read_counters();
  return out;
}

}  // namespace prismoid::surface
