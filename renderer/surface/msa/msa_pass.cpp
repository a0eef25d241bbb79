#include "renderer/surface/msa/msa_pass.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
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
#include "shaders/shared/msa.h"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

constexpr VkShaderStageFlags kStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_COMPUTE_BIT |
                                       VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
constexpr VkShaderStageFlags kPushStages = kStages & ~VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
constexpr uint64_t kSuperblockTexels = uint64_t(PRISMOID_MSA_SUPERBLOCK) * PRISMOID_MSA_SUPERBLOCK;

std::vector<vk::DescriptorBinding> msa_bindings() {
  std::vector<vk::DescriptorBinding> b = scene_bindings({.stages = kStages, .vertex_buffers = true, .tlas = false});
  b.push_back({PRISMOID_SURFACE_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  for (uint32_t binding = PRISMOID_MSA_BINDING_TRIANGLES; binding <= PRISMOID_MSA_BINDING_VISIBILITY; ++binding)
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  return b;
}

void compute_barrier(VkCommandBuffer cmd) {
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

const MsaSettings& checked(const vk::Device& device, const msa::MeshletSet& meshlets, const MsaSettings& s) {
  if (const std::string problem = msa_device_problem(device); !problem.empty()) throw vk::NoSuitableDevice(problem);
  const auto& caps = device.capabilities();
  if (s.superblocks == 0) throw InputError(setting("msa-superblocks"), "the atlas needs at least one superblock");
  const uint64_t bytes = uint64_t(s.superblocks) * kSuperblockTexels * 16;
  if (bytes > caps.max_storage_buffer_range)
    throw InputError(setting("msa-superblocks"), std::to_string(s.superblocks) + " superblocks (" + std::to_string(bytes) +
                                              " bytes) exceed the storage-buffer range of " + caps.name + " (" +
                                              std::to_string(caps.max_storage_buffer_range) + " bytes)");
  if (meshlets.meshlets.size() >= (1u << 20)) throw InputError("meshlets", "more than 2^20 meshlets");
  return s;
}

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout set) {
  const VkPushConstantRange push{kPushStages, 0, sizeof(gpu::MsaPush)};
  return vk::create_pipeline_layout(device, std::span(&set, 1), std::span(&push, 1));
}

template <typename T>
vk::Buffer upload(const vk::Device& device, std::vector<T> data) {
  if (data.empty()) data.resize(1);
  return vk::upload_buffer(device, std::as_bytes(std::span<const T>(data)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
}

}  // namespace

std::string msa_device_problem(const vk::Device& device) { return texture_space_device_problem(device, "the meshlet shading atlas"); }

MsaPass::MsaPass(const vk::Device& device, const msa::MeshletSet& meshlets, const MsaSettings& settings)
    : device_(device),
      meshlets_(meshlets),
      settings_(checked(device, meshlets, settings)),
      set_layout_(vk::create_descriptor_set_layout(device, msa_bindings())),
      layout_(make_layout(device, set_layout_.get())),
      shade_pipeline_(device, surface_rt_pipeline({"surface/msa/shade.rgen", "surface/msa/shade_unshadowed.rgen"}, layout_.get())) {
  const uint32_t n = settings.superblocks;
  columns_ = std::min(n, 8u);
  rows_ = (n + columns_ - 1) / columns_;
  const uint64_t meshlet_count = meshlets.meshlets.size();
  std::vector<gpu::MsaTriangleGpu> triangles(meshlets.corner_chart.size());
  for (size_t t = 0; t < triangles.size(); ++t) {
    const auto& c = meshlets.corner_chart[t];
    triangles[t].c01 = glm::vec4(float(c[0].x), float(c[0].y), float(c[1].x), float(c[1].y));
    triangles[t].c2 = glm::vec4(float(c[2].x), float(c[2].y), 0.0f, 0.0f);
    triangles[t].info = glm::uvec4(meshlets.meshlet_of_triangle[t], 0u, 0u, 0u);
  }
  std::vector<gpu::MsaMeshletGpu> table(meshlet_count);
  std::vector<uint32_t> list;
  for (size_t m = 0; m < meshlet_count; ++m) {
    const msa::Meshlet& ml = meshlets.meshlets[m];
    table[m].extent = glm::vec4(float(ml.extent.x), float(ml.extent.y), 0.0f, 0.0f);
    table[m].info = glm::uvec4(uint32_t(list.size()), uint32_t(ml.triangles.size()), 0u, 0u);
    std::vector<uint32_t> sorted = ml.triangles;
    std::sort(sorted.begin(), sorted.end());  // the lowest id first: the shading pass's rule on shared edges
    list.insert(list.end(), sorted.begin(), sorted.end());
  }
  triangles_ = upload(device, triangles);
  meshlet_table_ = upload(device, table);
  meshlet_triangles_ = upload(device, list);
  const uint64_t atlas_texels = uint64_t(columns_) * rows_ * kSuperblockTexels;
  blocks_ = vk::Buffer(device, std::max<uint64_t>(1, meshlet_count) * sizeof(gpu::MsaBlockGpu), kStorage, vk::MemoryUse::DeviceLocal);
  density_ = vk::Buffer(device, std::max<uint64_t>(1, meshlet_count) * 4, kStorage, vk::MemoryUse::DeviceLocal);
  classes_ = vk::Buffer(device, PRISMOID_MSA_CLASSES * sizeof(gpu::MsaClassGpu), kStorage, vk::MemoryUse::DeviceLocal);
  class_superblocks_ = vk::Buffer(device, uint64_t(PRISMOID_MSA_CLASSES) * n * 4, kStorage, vk::MemoryUse::DeviceLocal);
  free_slots_ = vk::Buffer(device, uint64_t(PRISMOID_MSA_CLASSES) * std::max<uint64_t>(1, meshlet_count) * 4, kStorage, vk::MemoryUse::DeviceLocal);
  pool_ = vk::Buffer(device, uint64_t(n) * 4, kStorage, vk::MemoryUse::DeviceLocal);
  state_ = vk::Buffer(device, sizeof(gpu::MsaStateGpu), kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                      vk::MemoryUse::DeviceLocal);
  tasks_ = vk::Buffer(device, atlas_texels / 64 * 4, kStorage, vk::MemoryUse::DeviceLocal);
  result_ = vk::Buffer(device, atlas_texels * 16, kStorage, vk::MemoryUse::DeviceLocal);
  readback_ = vk::Buffer(device, sizeof(gpu::MsaStateGpu), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), msa_bindings());
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  const VkDescriptorType s = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  const std::pair<uint32_t, const vk::Buffer*> buffers[] = {
      {PRISMOID_MSA_BINDING_TRIANGLES, &triangles_}, {PRISMOID_MSA_BINDING_MESHLETS, &meshlet_table_},
      {PRISMOID_MSA_BINDING_MESHLET_TRIANGLES, &meshlet_triangles_}, {PRISMOID_MSA_BINDING_BLOCKS, &blocks_},
      {PRISMOID_MSA_BINDING_DENSITY, &density_}, {PRISMOID_MSA_BINDING_CLASSES, &classes_},
      {PRISMOID_MSA_BINDING_CLASS_SUPERBLOCKS, &class_superblocks_}, {PRISMOID_MSA_BINDING_FREE_SLOTS, &free_slots_},
      {PRISMOID_MSA_BINDING_POOL, &pool_}, {PRISMOID_MSA_BINDING_STATE, &state_}, {PRISMOID_MSA_BINDING_TASKS, &tasks_},
      {PRISMOID_MSA_BINDING_RESULT, &result_}};
  for (const auto& [binding, buffer] : buffers) vk::write_buffer_descriptor(device, set_.set, binding, s, buffer->get());
  DepthThenVisiblePipelines mark = create_depth_then_visible(device, layout_.get(), "surface/msa/mark.frag");
  depth_pipeline_ = std::move(mark.depth);
  mark_pipeline_ = std::move(mark.visible);
  display_pipeline_ = create_fullscreen(device, layout_.get(), "surface/msa/display.frag");
  allocate_pipeline_ = vk::create_compute_pipeline(device, "surface/msa/allocate.comp", layout_.get());
  frame_charts_pipeline_ = vk::create_compute_pipeline(device, "surface/msa/frame_charts.comp", layout_.get());
  reset_atlas();
}

uint32_t MsaPass::atlas_width() const { return columns_ * PRISMOID_MSA_SUPERBLOCK; }
uint32_t MsaPass::atlas_height() const { return rows_ * PRISMOID_MSA_SUPERBLOCK; }

void MsaPass::set_settings(const MsaSettings& settings) {
  if (settings.superblocks != settings_.superblocks) throw std::invalid_argument("MsaPass: the atlas's size is fixed when the pass is made");
  settings_ = checked(device_, meshlets_, settings);
}

void MsaPass::reset_atlas() {
  const uint32_t n = settings_.superblocks;
  std::vector<uint32_t> pool(n);
  for (uint32_t i = 0; i < n; ++i) pool[i] = n - 1 - i;  // superblock 0 on top
  vk::Buffer staging(device_, pool.size() * 4, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::HostVisible);
  staging.write(std::as_bytes(std::span(pool)));
  std::vector<gpu::MsaBlockGpu> none(std::max<size_t>(1, meshlets_.meshlets.size()));
  for (auto& b : none) b.block = glm::uvec4(0u, 0u, PRISMOID_MSA_NONE, 0u);
  vk::Buffer blocks(device_, none.size() * sizeof(gpu::MsaBlockGpu), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::HostVisible);
  blocks.write(std::as_bytes(std::span(none)));
  gpu::MsaStateGpu state{};
  state.pool.x = n;
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkBufferCopy pool_copy{0, 0, pool.size() * 4};
    vkCmdCopyBuffer(cmd, staging.get(), pool_.get(), 1, &pool_copy);
    const VkBufferCopy block_copy{0, 0, none.size() * sizeof(gpu::MsaBlockGpu)};
    vkCmdCopyBuffer(cmd, blocks.get(), blocks_.get(), 1, &block_copy);
    vkCmdFillBuffer(cmd, classes_.get(), 0, VK_WHOLE_SIZE, 0u);
    vkCmdFillBuffer(cmd, result_.get(), 0, VK_WHOLE_SIZE, 0u);
    vkCmdUpdateBuffer(cmd, state_.get(), 0, sizeof(state), &state);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
}

void MsaPass::bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const MsaTargets& targets) {
  if (scene.triangle_count != meshlets_.corner_chart.size())
    throw std::invalid_argument("MsaPass: the GPU scene is not the one the meshlets were built from");
  bound_.update(device_, set_.set, scene, tlas, targets.visibility, PRISMOID_MSA_BINDING_VISIBILITY);
}

void MsaPass::record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, MsaTargets& targets,
                     const Camera& camera, vk::GpuTimer& timer) {
  validate(camera);
  if (frame_stamp_ > 0) {
    gpu::MsaStateGpu last{};
    std::memcpy(&last, readback_.mapped(), sizeof(last));
    if (last.pool.z != 0 || last.pool.w != 0) {  // the atlas ran out last frame: start over, compacted
      reset_atlas();
      invalidate_ = true;
    }
  }
  bind(scene, tlas, targets);
  const VkExtent2D e = targets.extent;
  const gpu::SurfaceFrame frame = surface_frame(scene, camera, e, glm::dvec2(0.0));
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));
  frame_stamp_ += 1;
  const bool periodic = settings_.shade_every > 0 && ++frames_since_shading_ >= settings_.shade_every;
  const bool shade_all = std::exchange(invalidate_, false) || periodic;
  if (shade_all) frames_since_shading_ = 0;

  gpu::MsaPush push{};
  const bool frame_charts = msa::per_frame(settings_.frame_charts);
  const uint32_t chart_flags = frame_charts ? PRISMOID_MSA_FLAG_FRAME_CHARTS | (settings_.frame_charts == msa::Parametrization::Perspective
                                                                                    ? PRISMOID_MSA_FLAG_PERSPECTIVE
                                                                                    : 0u)
                                            : 0u;
  push.image = glm::uvec4(e.width, e.height,
                          (settings_.shadows ? PRISMOID_MSA_FLAG_SHADOWS : 0u) | (shade_all ? PRISMOID_MSA_FLAG_SHADE_ALL : 0u) | chart_flags,
                          frame_stamp_);
  const uint32_t meshlet_count = uint32_t(meshlets_.meshlets.size());
  push.atlas = glm::uvec4(atlas_width(), columns_, meshlet_count, 0u);
  push.limits = glm::uvec4(settings_.superblocks, settings_.budget_texels, std::bit_cast<uint32_t>(float(camera.near_distance)), 0u);
  const PassBinding binding{layout_.get(), set_.set, kPushStages, std::as_bytes(std::span(&push, 1))};

  // This frame's densities, counters and visibility start at zero; blocks, classes, pool and atlas carry over.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(cmd, targets.visibility.get(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, density_.get(), 0, VK_WHOLE_SIZE, 0u);
  // Everything but pool.x (the free superblocks) starts at zero.
  vkCmdUpdateBuffer(cmd, state_.get(), 0, sizeof(glm::uvec4), std::array<uint32_t, 4>{8u, 8u * PRISMOID_MSA_TILES_PER_LAUNCH, 0u, 0u}.data());
  vkCmdFillBuffer(cmd, state_.get(), offsetof(gpu::MsaStateGpu, pool) + 4, sizeof(gpu::MsaStateGpu) - offsetof(gpu::MsaStateGpu, pool) - 4, 0u);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  {
    vk::ScopedPass pass(timer, cmd, "pre-z + visibility");
    if (frame_charts) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, frame_charts_pipeline_.get());
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
      vkCmdPushConstants(cmd, layout_.get(), kPushStages, 0, sizeof(push), &push);
      const uint32_t groups = (std::max(1u, meshlet_count) + 63) / 64, x = std::min(groups, 32768u);
      vkCmdDispatch(cmd, x, (groups + x - 1) / x, 1);
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                         VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT |
                             VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                         VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    }
    record_depth_then_visible(cmd, scene, targets.depth, e, depth_pipeline_.get(), mark_pipeline_.get(), binding);
  }
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  {
    vk::ScopedPass pass(timer, cmd, "block management");
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, allocate_pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
    const uint32_t per_meshlet = std::max(1u, meshlet_count), per_class = PRISMOID_MSA_CLASSES;
    const std::pair<uint32_t, uint32_t> steps[] = {
        {PRISMOID_MSA_STEP_DEMAND, per_meshlet}, {PRISMOID_MSA_STEP_BUDGET, 1},   {PRISMOID_MSA_STEP_RELEASE, per_meshlet},
        {PRISMOID_MSA_STEP_CLAIM, per_class},    {PRISMOID_MSA_STEP_POOL, 1},     {PRISMOID_MSA_STEP_ALLOCATE, per_meshlet},
        {PRISMOID_MSA_STEP_SETTLE, per_class},   {PRISMOID_MSA_STEP_TASKS, per_meshlet}};
    for (const auto& [step, invocations] : steps) {
      push.atlas.w = step;
      vkCmdPushConstants(cmd, layout_.get(), kPushStages, 0, sizeof(push), &push);
      const uint32_t groups = (invocations + 63) / 64, x = std::min(groups, 32768u);
      vkCmdDispatch(cmd, x, (groups + x - 1) / x, 1);
      compute_barrier(cmd);
    }
    push.atlas.w = 0;
  }
  record_indirect_shading(cmd, timer, shade_pipeline_, settings_.shadows ? 0 : 1, binding, state_.device_address());
  {
    vk::ScopedPass pass(timer, cmd, "display");
    record_fullscreen(cmd, targets.color, e, display_pipeline_.get(), binding);
  }
  record_state_readback(cmd, state_, readback_, sizeof(gpu::MsaStateGpu));
}

MsaCounters MsaPass::read_counters() const {
  const auto s = read_mapped<gpu::MsaStateGpu>(readback_);
  MsaCounters c;
  c.seen_meshlets = s.blocks.x;
  c.allocated_blocks = s.blocks.y;
  c.released_blocks = s.blocks.z;
  c.shaded_blocks = s.blocks.w;
  c.shaded_tiles = s.demand.w;
  c.shading_launch = s.trace.z;
  c.shaded_texels = s.trace.w;
  c.free_superblocks = s.pool.x;
  c.out_of_superblocks = s.pool.z != 0;
  c.meshlets_without_block = s.pool.w;
  c.hole_pixels = s.demand.z;
  c.demand_texels = s.demand.x;
  c.held_texels = s.demand.y;
  c.budget_factor = s.budget.x;
  if (s.stretch.y > 0) {
    const double sum = (double(s.stretch.w) * 4294967296.0 + double(s.stretch.x)) / 4096.0;
    c.stretch_l2 = std::sqrt(sum / double(s.stretch.y));
    c.stretch_linf = double(std::bit_cast<float>(s.stretch.z));
  }
  c.atlas_bytes = result_.size() + tasks_.size() + blocks_.size() + free_slots_.size() + class_superblocks_.size() + triangles_.size() +
                  meshlet_table_.size() + meshlet_triangles_.size();
  return c;
}

std::vector<std::byte> MsaPass::read_buffer(const vk::Buffer& buffer) const { return read_device_buffer(device_, buffer); }

MsaImage render_msa(const vk::Device& device, MsaPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const Camera& camera,
                    VkExtent2D extent) {
  return render_texture_space_frame<MsaImage>(device, pass, scene, tlas, camera, extent);
}

}  // namespace prismoid::surface
