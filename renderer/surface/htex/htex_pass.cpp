#include "renderer/surface/htex/htex_pass.hpp"

#include <utility>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <stdexcept>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/surface/surface_frame.hpp"
#include "renderer/surface/texture_space_passes.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/graphics_pipeline.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/htex.h"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

constexpr VkFormat kColorFormat = kTextureSpaceColorFormat;
constexpr VkFormat kDepthFormat = kTextureSpaceDepthFormat;
constexpr VkShaderStageFlags kStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_COMPUTE_BIT |
                                       VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;

// allocate.comp's steps.
enum Step : uint32_t { kCount = 0, kDecide, kClear, kRemark, kRelease, kAllocate, kFinish, kTasks };

std::vector<vk::DescriptorBinding> htex_bindings() {
  std::vector<vk::DescriptorBinding> b = scene_bindings({.stages = kStages, .vertex_buffers = true, .tlas = false});
  b.push_back({PRISMOID_SURFACE_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  for (const auto& t : htex_table_bindings(kStages)) b.push_back(t);
  for (uint32_t binding = PRISMOID_HTEX_BINDING_OCCUPANCY; binding <= PRISMOID_HTEX_BINDING_VISIBILITY; ++binding)
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  b.push_back({PRISMOID_HTEX_BINDING_SHADED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  return b;
}

void compute_barrier(VkCommandBuffer cmd) {
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void check_device(const vk::Device& device) {
  if (const std::string problem = htex_device_problem(device); !problem.empty()) throw vk::NoSuitableDevice(problem);
}

uint32_t checked_pages(const vk::Device& device, uint32_t pages) {
  const auto& caps = device.capabilities();
  if (pages == 0) throw InputError(setting("pool-pages"), "the pool needs at least one page");
  const uint64_t bytes = uint64_t(pages) * PRISMOID_HTEX_PAGE_TEXELS * 16;
  if (bytes > caps.max_storage_buffer_range)
    throw InputError(setting("pool-pages"), std::to_string(pages) + " pages (" + std::to_string(bytes) + " bytes) exceed the storage-buffer range of " +
                                         caps.name + " (" + std::to_string(caps.max_storage_buffer_range) + " bytes)");
  if (uint64_t(pages) * PRISMOID_HTEX_PAGE_TEXELS > caps.max_ray_dispatch_invocations)
    throw InputError(setting("pool-pages"), std::to_string(pages) + " pages hold more texels than " + caps.name + " can shade in one launch");
  return pages;
}

rt::RayTracingPipelineDesc shade_desc(VkPipelineLayout layout) {
  return surface_rt_pipeline({"surface/htex/shade.rgen", "surface/htex/shade_unshadowed.rgen"}, layout);
}

PassBinding pass_binding(VkPipelineLayout layout, VkDescriptorSet set, const gpu::HtexPush& push) {
  return {layout, set, kStages & ~VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR, std::as_bytes(std::span(&push, 1))};
}

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout set) {
  const VkPushConstantRange push{kStages & ~VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR, 0, sizeof(gpu::HtexPush)};
  return vk::create_pipeline_layout(device, std::span(&set, 1), std::span(&push, 1));
}

}  // namespace

std::string htex_device_problem(const vk::Device& device) { return texture_space_device_problem(device, "the Htex backend"); }

HtexPass::HtexPass(const vk::Device& device, const HtexGeometry& geometry, const HtexSettings& settings)
    : device_(device),
      geometry_(geometry),
      settings_(settings),
      tables_((check_device(device), upload_htex_tables(device, geometry, checked_pages(device, settings.pool_pages)))),
      set_layout_(vk::create_descriptor_set_layout(device, htex_bindings())),
      layout_(make_layout(device, set_layout_.get())),
      shade_pipeline_(device, shade_desc(layout_.get())) {
  const std::vector<vk::DescriptorBinding> bindings = htex_bindings();
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), bindings);
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  write_htex_table_descriptors(device, set_.set, tables_);

  const uint64_t groups = geometry.group_count(), pages = settings.pool_pages;
  occupancy_ = vk::Buffer(device, groups * 8, kStorage, vk::MemoryUse::DeviceLocal);
  page_table_ = vk::Buffer(device, groups * 4, kStorage, vk::MemoryUse::DeviceLocal);
  shaded_ = vk::Buffer(device, groups * 8, kStorage, vk::MemoryUse::DeviceLocal);
  free_list_ = vk::Buffer(device, pages * 4, kStorage, vk::MemoryUse::DeviceLocal);
  state_ = vk::Buffer(device, sizeof(gpu::HtexStateGpu),
                      kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, vk::MemoryUse::DeviceLocal);
  tasks_ = vk::Buffer(device, pages * 64 * 4, kStorage, vk::MemoryUse::DeviceLocal);
  pool_ = vk::Buffer(device, pages * PRISMOID_HTEX_PAGE_TEXELS * 16, kStorage, vk::MemoryUse::DeviceLocal);
  indirect_ = vk::Buffer(device, settings.indirect ? pages * PRISMOID_HTEX_PAGE_TEXELS * 16 : 16, kStorage, vk::MemoryUse::DeviceLocal);
  readback_ = vk::Buffer(device, sizeof(gpu::HtexStateGpu), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  const VkDescriptorType s = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_OCCUPANCY, s, occupancy_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_PAGE_TABLE, s, page_table_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_SHADED, s, shaded_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_FREE_LIST, s, free_list_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_STATE, s, state_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_TASKS, s, tasks_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_POOL, s, pool_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_HTEX_BINDING_INDIRECT, s, indirect_.get());

  DepthThenVisiblePipelines marking = create_depth_then_visible(device, layout_.get(), "surface/htex/mark.frag");
  depth_pipeline_ = std::move(marking.depth);
  mark_pipeline_ = std::move(marking.visible);
  gather_pipeline_ = create_fullscreen(device, layout_.get(), "surface/htex/gather.frag");
  allocate_pipeline_ = vk::create_compute_pipeline(device, "surface/htex/allocate.comp", layout_.get());
  set_settings(settings);
  reset_residency();
}

void HtexPass::set_settings(const HtexSettings& settings) {
  if (settings.pool_pages != settings_.pool_pages || settings.indirect != settings_.indirect)
    throw std::invalid_argument("HtexPass: the pool's size and the indirect buffer are fixed when the pass is made");
  settings_ = settings;
  flags_ = (settings.snap_vertex_corners ? 0u : PRISMOID_HTEX_FLAG_NO_SNAP) | (settings.indirect ? PRISMOID_HTEX_FLAG_INDIRECT : 0u) |
           (settings.reuse_shading ? PRISMOID_HTEX_FLAG_REUSE : 0u);
}

void HtexPass::reset_residency() {
  const uint32_t pages = settings_.pool_pages;
  std::vector<uint32_t> free(pages);
  for (uint32_t i = 0; i < pages; ++i) free[i] = pages - 1 - i;  // page 0 on top
  vk::Buffer staging(device_, free.size() * 4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::HostVisible);
  staging.write(std::as_bytes(std::span(free)));
  gpu::HtexStateGpu state{};
  state.persistent.x = pages;
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    vkCmdFillBuffer(cmd, page_table_.get(), 0, VK_WHOLE_SIZE, PRISMOID_HTEX_NOT_RESIDENT);
    vkCmdFillBuffer(cmd, shaded_.get(), 0, VK_WHOLE_SIZE, 0u);
    const VkBufferCopy copy{0, 0, free.size() * 4};
    vkCmdCopyBuffer(cmd, staging.get(), free_list_.get(), 1, &copy);
    vkCmdUpdateBuffer(cmd, state_.get(), 0, sizeof(state), &state);
    vkCmdFillBuffer(cmd, pool_.get(), 0, VK_WHOLE_SIZE, 0u);
    if (settings_.indirect) vkCmdFillBuffer(cmd, indirect_.get(), 0, VK_WHOLE_SIZE, 0u);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
}

void HtexPass::bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const HtexTargets& targets) {
  if (scene.triangle_count != geometry_.triangle_count)
    throw std::invalid_argument("HtexPass: the GPU scene is not the one the Htex geometry was built from");
  bound_.update(device_, set_.set, scene, tlas, targets.visibility, PRISMOID_HTEX_BINDING_VISIBILITY);
}

void HtexPass::push_step(VkCommandBuffer cmd, uint32_t step) {
  gpu::HtexPush push{};
  push.image = glm::uvec4(extent_.width, extent_.height, flags_, step);
  push.lod = glm::vec4(settings_.lod_bias, 0.0f, 0.0f, 0.0f);
  vkCmdPushConstants(cmd, layout_.get(), kStages & ~VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR, 0, sizeof(push), &push);
}

void HtexPass::dispatch_step(VkCommandBuffer cmd, uint32_t step, uint32_t invocations) {
  push_step(cmd, step);
  const uint32_t groups = std::max(1u, (invocations + 63) / 64);
  const uint32_t x = std::min(groups, PRISMOID_HTEX_DISPATCH_ROW);
  vkCmdDispatch(cmd, x, (groups + x - 1) / x, 1);
}

void HtexPass::record_marking(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, HtexTargets& targets,
                              const Camera& camera, vk::GpuTimer& timer) {
  validate(camera);
  bind(scene, tlas, targets);
  extent_ = targets.extent;
  const VkExtent2D e = targets.extent;
  gpu::SurfaceFrame frame = surface_frame(scene, camera, e, glm::dvec2(0.0));
  if (!settings_.sky_ambient) frame.sky_up.w = 1.0f;  // shade_surface_point leaves the sky's ambient term to GI
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));

  // This frame's counters, occupancy and visibility start at zero; the page table, free list and
  // pool carry over.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(cmd, occupancy_.get(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, targets.visibility.get(), 0, VK_WHOLE_SIZE, 0u);
  if (std::exchange(invalidate_, false)) vkCmdFillBuffer(cmd, shaded_.get(), 0, VK_WHOLE_SIZE, 0u);
  gpu::HtexStateGpu fresh{};
  fresh.trace = glm::uvec4(8u, 8u, 0u, 0u);
  vkCmdUpdateBuffer(cmd, state_.get(), 0, offsetof(gpu::HtexStateGpu, persistent), &fresh);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);

  vk::ScopedPass pass(timer, cmd, "pre-z + marking");
  gpu::HtexPush push{};
  push.image = glm::uvec4(e.width, e.height, flags_, 0u);
  push.lod = glm::vec4(settings_.lod_bias, 0.0f, 0.0f, 0.0f);
  record_depth_then_visible(cmd, scene, targets.depth, e, depth_pipeline_.get(), mark_pipeline_.get(), pass_binding(layout_.get(), set_.set, push));
}

void HtexPass::record_allocation(VkCommandBuffer cmd, const HtexTargets&, vk::GpuTimer& timer) {
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  vk::ScopedPass pass(timer, cmd, "allocation");
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, allocate_pipeline_.get());
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
  const uint32_t groups = geometry_.group_count();
  auto step = [&](uint32_t s, uint32_t invocations) {
    dispatch_step(cmd, s, invocations);
    compute_barrier(cmd);
  };
  // The loop's later steps are sized by DECIDE (HtexStateGpu::loop_groups, loop_pixels): once the
  // marked groups fit, its remaining iterations launch nothing instead of every group and pixel
  // only to return, since most frames need no bias.
  auto sized_by_decide = [&](uint32_t s, VkDeviceSize offset) {
    push_step(cmd, s);
    vkCmdDispatchIndirect(cmd, state_.get(), offset);
    compute_barrier(cmd);
  };
  auto decide = [&] {
    dispatch_step(cmd, kDecide, 1);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                       VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                       VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  };
  // Count and decide; while over capacity (and a coarser level is left), bias and re-mark.
  step(kCount, groups);
  decide();
  for (uint32_t iteration = 1; iteration < geometry_.max_levels; ++iteration) {
    sized_by_decide(kClear, offsetof(gpu::HtexStateGpu, loop_groups));
    sized_by_decide(kRemark, offsetof(gpu::HtexStateGpu, loop_pixels));
    sized_by_decide(kCount, offsetof(gpu::HtexStateGpu, loop_groups));
    decide();
  }
  step(kRelease, groups);
  step(kAllocate, groups);
  step(kFinish, 1);
  dispatch_step(cmd, kTasks, groups);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR |
                         VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void HtexPass::record_shading(VkCommandBuffer cmd, const HtexTargets&, vk::GpuTimer& timer) {
  gpu::HtexPush push{};
  push.image = glm::uvec4(extent_.width, extent_.height, flags_, 0u);
  record_indirect_shading(cmd, timer, shade_pipeline_, settings_.shadows ? 0 : 1, pass_binding(layout_.get(), set_.set, push), state_.device_address());
}

void HtexPass::record_gather(VkCommandBuffer cmd, HtexTargets& targets, vk::GpuTimer& timer) {
  const VkExtent2D e = targets.extent;
  {
    vk::ScopedPass pass(timer, cmd, "gather");
    gpu::HtexPush push{};
    push.image = glm::uvec4(e.width, e.height, flags_, 0u);
    record_fullscreen(cmd, targets.color, e, gather_pipeline_.get(), pass_binding(layout_.get(), set_.set, push));
  }
  record_state_readback(cmd, state_, readback_, sizeof(gpu::HtexStateGpu));
}

void HtexPass::record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, HtexTargets& targets,
                      const Camera& camera, vk::GpuTimer& timer) {
  record_marking(cmd, scene, tlas, targets, camera, timer);
  record_allocation(cmd, targets, timer);
  record_shading(cmd, targets, timer);
  record_gather(cmd, targets, timer);
}

HtexCounters HtexPass::read_counters() const {
  const auto s = read_mapped<gpu::HtexStateGpu>(readback_);
  HtexCounters c;
  c.marked_groups = s.marking.x;
  c.marked_shadels = s.marking.y;
  c.bias_levels = s.marking.z;
  c.marked_groups_unbiased = s.result.z;
  c.overflow = s.result.x != 0;
  c.hole_pixels = s.result.y;
  c.released_pages = s.pages.x;
  c.allocated_pages = s.pages.y;
  c.unallocated_groups = s.pages.z;
  c.resident_groups = s.pages.w;
  c.free_pages = s.persistent.x;
  c.shaded_shadels = s.trace.z;
  c.reused_shadels = s.result.w;
  c.shaded_texels = s.trace.w;
  c.pool_bytes = pool_.size() + (settings_.indirect ? indirect_.size() : 0);
  return c;
}

std::vector<std::byte> HtexPass::read_buffer(const vk::Buffer& buffer) const { return read_device_buffer(device_, buffer); }

HtexImage render_htex(const vk::Device& device, HtexPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                      const Camera& camera, VkExtent2D extent) {
  return render_texture_space_frame<HtexImage>(device, pass, scene, tlas, camera, extent);
}

}  // namespace prismoid::surface
