#include "renderer/surface/texel/texel_pass.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/surface/surface_frame.hpp"
#include "renderer/surface/texture_space_passes.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/surface.h"
#include "shaders/shared/texel.h"

namespace prismoid::surface {

namespace {

constexpr VkShaderStageFlags kStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_RAYGEN_BIT_KHR |
                                       VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
constexpr VkShaderStageFlags kPushStages = kStages & ~VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;

std::vector<vk::DescriptorBinding> texel_bindings() {
  std::vector<vk::DescriptorBinding> b = scene_bindings({.stages = kStages, .vertex_buffers = true, .tlas = false});
  b.push_back({PRISMOID_SURFACE_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  for (uint32_t binding = PRISMOID_TEXEL_BINDING_TRIANGLES; binding <= PRISMOID_TEXEL_BINDING_VISIBILITY; ++binding)
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  return b;
}

void check_device(const vk::Device& device) {
  if (const std::string problem = texel_device_problem(device); !problem.empty()) throw vk::NoSuitableDevice(problem);
}

const texel::TexelAtlas& checked_atlas(const vk::Device& device, const texel::TexelAtlas& atlas) {
  check_device(device);
  const auto& caps = device.capabilities();
  const uint64_t bytes = atlas.texel_count() * 16;
  if (bytes > caps.max_storage_buffer_range)
    throw InputError(setting("texel-density"), "the texel atlas (" + std::to_string(atlas.width) + " x " + std::to_string(atlas.height) + ", " +
                                            std::to_string(bytes) + " bytes of results) exceeds the storage-buffer range of " + caps.name +
                                            " (" + std::to_string(caps.max_storage_buffer_range) + " bytes): lower the density");
  if (atlas.levels > PRISMOID_TEXEL_MAX_LEVELS) throw InputError(setting("texel-levels"), "at most 8 levels");
  return atlas;
}

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout set) {
  const VkPushConstantRange push{kPushStages, 0, sizeof(gpu::TexelPush)};
  return vk::create_pipeline_layout(device, std::span(&set, 1), std::span(&push, 1));
}

template <typename T>
vk::Buffer upload(const vk::Device& device, std::vector<T> data) {
  if (data.empty()) data.resize(1);  // storage buffers cannot be empty
  return vk::upload_buffer(device, std::as_bytes(std::span<const T>(data)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
}

std::vector<gpu::TexelTriangleGpu> triangle_table(const texel::TexelAtlas& atlas) {
  std::vector<gpu::TexelTriangleGpu> out(atlas.corner_uv.size());
  const uint32_t pad = texel::padding_texels(atlas.levels);
  for (size_t t = 0; t < out.size(); ++t) {
    const texel::Chart& chart = atlas.charts[atlas.chart_of_triangle[t]];
    const glm::dvec2 origin = glm::dvec2(chart.origin + glm::uvec2(pad));
    const auto& uv = atlas.corner_uv[t];
    const glm::dvec2 a = uv[0] - origin, b = uv[1] - origin, c = uv[2] - origin;
    out[t].uv01 = glm::vec4(float(a.x), float(a.y), float(b.x), float(b.y));
    out[t].uv2 = glm::vec4(float(c.x), float(c.y), 0.0f, 0.0f);
    out[t].origin = glm::uvec4(chart.origin.x + pad, chart.origin.y + pad, atlas.chart_of_triangle[t], 0u);
  }
  return out;
}

std::vector<uint32_t> index_texture(const texel::TexelAtlas& atlas) {
  std::vector<uint32_t> out;
  out.reserve(atlas.texel_count());
  for (const auto& level : atlas.triangle_index) out.insert(out.end(), level.begin(), level.end());
  return out;
}

}  // namespace

std::string texel_device_problem(const vk::Device& device) { return texture_space_device_problem(device, "texel shading"); }

texel::TexelAtlas build_texel_atlas_for(const vk::Device& device, const SurfaceScene& scene, texel::AtlasSettings settings) {
  const uint64_t range = device.capabilities().max_storage_buffer_range;
  for (;;) {
    texel::TexelAtlas atlas = texel::build_texel_atlas(scene, settings);
    if (settings.texels_per_unit > 0.0 || atlas.texel_count() * 16 <= range || settings.target_texels < 1024.0) return atlas;
    settings.target_texels *= 0.5;
  }
}

TexelPass::TexelPass(const vk::Device& device, const texel::TexelAtlas& atlas, const TexelSettings& settings)
    : device_(device),
      atlas_(checked_atlas(device, atlas)),
      settings_(settings),
      set_layout_(vk::create_descriptor_set_layout(device, texel_bindings())),
      layout_(make_layout(device, set_layout_.get())),
      shade_pipeline_(device, surface_rt_pipeline({"surface/texel/shade.rgen", "surface/texel/shade_unshadowed.rgen"}, layout_.get())) {
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), texel_bindings());
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  triangles_ = upload(device, triangle_table(atlas));
  triangle_index_ = upload(device, index_texture(atlas));
  cache_ = vk::Buffer(device, std::max<uint64_t>(16, atlas.tile_count() * 4), kStorage, vk::MemoryUse::DeviceLocal);
  tasks_ = vk::Buffer(device, std::max<uint64_t>(16, atlas.tile_count() * 4), kStorage, vk::MemoryUse::DeviceLocal);
  result_ = vk::Buffer(device, std::max<uint64_t>(16, atlas.texel_count() * 16), kStorage, vk::MemoryUse::DeviceLocal);
  state_ = vk::Buffer(device, sizeof(gpu::TexelStateGpu), kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                      vk::MemoryUse::DeviceLocal);
  readback_ = vk::Buffer(device, sizeof(gpu::TexelStateGpu), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  const VkDescriptorType s = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_TEXEL_BINDING_TRIANGLES, s, triangles_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_TEXEL_BINDING_TRIANGLE_INDEX, s, triangle_index_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_TEXEL_BINDING_CACHE, s, cache_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_TEXEL_BINDING_TASKS, s, tasks_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_TEXEL_BINDING_RESULT, s, result_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_TEXEL_BINDING_STATE, s, state_.get());
  DepthThenVisiblePipelines queue = create_depth_then_visible(device, layout_.get(), "surface/texel/queue.frag");
  depth_pipeline_ = std::move(queue.depth);
  queue_pipeline_ = std::move(queue.visible);
  gather_pipeline_ = create_fullscreen(device, layout_.get(), "surface/texel/gather.frag");
  set_settings(settings);
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, cache_.get(), 0, VK_WHOLE_SIZE, 0u);
    vkCmdFillBuffer(cmd, result_.get(), 0, VK_WHOLE_SIZE, 0u);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
}

void TexelPass::set_settings(const TexelSettings& settings) {
  if (settings.max_age == 0) throw InputError(setting("texel-max-age"), "the age threshold is at least 1 frame");
  settings_ = settings;
}

void TexelPass::bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const TexelTargets& targets) {
  if (scene.triangle_count != atlas_.corner_uv.size())
    throw std::invalid_argument("TexelPass: the GPU scene is not the one the texel atlas was built from");
  bound_.update(device_, set_.set, scene, tlas, targets.visibility, PRISMOID_TEXEL_BINDING_VISIBILITY);
}

void TexelPass::record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, TexelTargets& targets,
                       const Camera& camera, vk::GpuTimer& timer) {
  validate(camera);
  bind(scene, tlas, targets);
  const VkExtent2D e = targets.extent;
  const gpu::SurfaceFrame frame = surface_frame(scene, camera, e, glm::dvec2(0.0));
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));
  frame_stamp_ += 1;

  gpu::TexelPush push{};
  push.image = glm::uvec4(e.width, e.height, settings_.shadows ? PRISMOID_TEXEL_FLAG_SHADOWS : 0u, frame_stamp_);
  push.atlas = glm::uvec4(atlas_.width, atlas_.height, atlas_.levels, settings_.max_age);
  for (uint32_t l = 0; l < 8; ++l) {
    const uint32_t texels = l < atlas_.levels ? uint32_t(atlas_.texel_offset(l)) : 0u;
    const uint32_t tiles = l < atlas_.levels ? uint32_t(atlas_.tile_offset(l)) : 0u;
    (l < 4 ? push.texel_offset0 : push.texel_offset1)[l % 4] = texels;
    (l < 4 ? push.tile_offset0 : push.tile_offset1)[l % 4] = tiles;
  }
  push.lod = glm::vec4(settings_.lod_bias, 0.0f, 0.0f, 0.0f);
  const PassBinding binding{layout_.get(), set_.set, kPushStages, std::as_bytes(std::span(&push, 1))};

  // This frame's counters and visibility start at zero; the cache and the results carry over.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(cmd, targets.visibility.get(), 0, VK_WHOLE_SIZE, 0u);
  if (std::exchange(invalidate_, false)) vkCmdFillBuffer(cmd, cache_.get(), 0, VK_WHOLE_SIZE, 0u);
  gpu::TexelStateGpu fresh{};
  fresh.trace = glm::uvec4(8u, 8u, 0u, 0u);
  vkCmdUpdateBuffer(cmd, state_.get(), 0, sizeof(fresh), &fresh);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  {
    vk::ScopedPass pass(timer, cmd, "pre-z + queue");
    record_depth_then_visible(cmd, scene, targets.depth, e, depth_pipeline_.get(), queue_pipeline_.get(), binding);
  }
  record_indirect_shading(cmd, timer, shade_pipeline_, settings_.shadows ? 0 : 1, binding, state_.device_address());
  {
    vk::ScopedPass pass(timer, cmd, "gather");
    record_fullscreen(cmd, targets.color, e, gather_pipeline_.get(), binding);
  }
  record_state_readback(cmd, state_, readback_, sizeof(gpu::TexelStateGpu));
}

TexelCounters TexelPass::read_counters() const {
  const auto s = read_mapped<gpu::TexelStateGpu>(readback_);
  TexelCounters c;
  c.queued_tiles = s.trace.z;
  c.shaded_texels = s.trace.w;
  c.hole_pixels = s.counts.y;
  c.atlas_bytes = result_.size() + triangle_index_.size() + cache_.size() + tasks_.size() + triangles_.size();
  return c;
}

std::vector<std::byte> TexelPass::read_buffer(const vk::Buffer& buffer) const { return read_device_buffer(device_, buffer); }

TexelImage render_texel(const vk::Device& device, TexelPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                        const Camera& camera, VkExtent2D extent) {
  return render_texture_space_frame<TexelImage>(device, pass, scene, tlas, camera, extent);
}

}  // namespace prismoid::surface
