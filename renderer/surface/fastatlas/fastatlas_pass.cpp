#include "renderer/surface/fastatlas/fastatlas_pass.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/fastatlas/atlas_packing.hpp"
#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/surface/surface_frame.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/fastatlas.h"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

constexpr VkShaderStageFlags kStages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT | VK_SHADER_STAGE_COMPUTE_BIT |
                                       VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
constexpr VkShaderStageFlags kPushStages = kStages & ~VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
constexpr VkFormat kIdFormat = VK_FORMAT_R32_UINT;
constexpr VkFormat kAtlasColorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkPipelineStageFlags2 kShaderStages = VK_PIPELINE_STAGE_2_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
                                                VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR;
constexpr VkAccessFlags2 kShaderAccess = VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;

std::vector<vk::DescriptorBinding> fastatlas_bindings() {
  std::vector<vk::DescriptorBinding> b = scene_bindings({.stages = kStages, .vertex_buffers = true, .tlas = false});
  b.push_back({PRISMOID_SURFACE_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  for (uint32_t binding = PRISMOID_FA_BINDING_TRIANGLES; binding <= PRISMOID_FA_BINDING_VISIBILITY; ++binding)
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  b.push_back({PRISMOID_FA_BINDING_ID_ATLAS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kStages});
  b.push_back({PRISMOID_FA_BINDING_COLOR_ATLAS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kStages});
  b.push_back({PRISMOID_FA_BINDING_SCALES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  b.push_back({PRISMOID_FA_BINDING_DEPTH_ATLAS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kStages});
  b.push_back({PRISMOID_FA_BINDING_HISTORY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  b.push_back({PRISMOID_FA_BINDING_VISIBLE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  b.push_back({PRISMOID_FA_BINDING_PREV_COLOR, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kStages});
  for (uint32_t binding = PRISMOID_FA_BINDING_PREV_PARENT; binding <= PRISMOID_FA_BINDING_PREV_STATE; ++binding)
    b.push_back({binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  b.push_back({PRISMOID_FA_BINDING_PREV_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kStages});
  b.push_back({PRISMOID_FA_BINDING_RASTER_CHUNKS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kStages});
  return b;
}

void check_device(const vk::Device& device) {
  if (const std::string problem = fastatlas_device_problem(device); !problem.empty()) throw vk::NoSuitableDevice(problem);
}

const FastAtlasSettings& checked(const vk::Device& device, const FastAtlasSettings& s) {
  check_device(device);
  const uint32_t w = s.atlas_width, h = s.atlas_height, most = device.capabilities().max_image_dimension_2d;
  if (w < 64 || (w & (w - 1)) != 0) throw InputError(setting("atlas"), "the atlas width must be a power of two of at least 64 (got " + std::to_string(w) + ")");
  if (h < 64) throw InputError(setting("atlas"), "the atlas height must be at least 64 texels (got " + std::to_string(h) + ")");
  if (w > most || h > most)
    throw InputError(setting("atlas"), "a " + std::to_string(w) + " x " + std::to_string(h) + " atlas exceeds the largest image of " +
                                    device.capabilities().name + " (" + std::to_string(most) + " texels a side)");
  if (!(s.shading_scale > 0.0) || !(s.shading_scale <= 4.0))
    throw InputError(setting("shading-scale"), "the shading scale SF must lie in (0, 4] (got " + std::to_string(s.shading_scale) + ")");
  return s;
}

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout set) {
  const VkPushConstantRange push{kPushStages, 0, sizeof(gpu::FaPush)};
  return vk::create_pipeline_layout(device, std::span(&set, 1), std::span(&push, 1));
}

vk::Buffer storage(const vk::Device& device, uint64_t bytes, VkBufferUsageFlags extra = 0) {
  return vk::Buffer(device, std::max<uint64_t>(16, bytes), kStorage | extra, vk::MemoryUse::DeviceLocal);
}

std::vector<gpu::FaTriangleGpu> triangle_table(const fastatlas::SceneAdjacency& a) {
  std::vector<gpu::FaTriangleGpu> out(a.neighbours.size());
  for (size_t t = 0; t < out.size(); ++t) {
    out[t].neighbours = glm::uvec4(a.neighbours[t][0], a.neighbours[t][1], a.neighbours[t][2], a.smooth[t]);
    out[t].vertices = glm::uvec4(a.vertices[t][0], a.vertices[t][1], a.vertices[t][2], 0u);
  }
  if (out.empty()) out.resize(1);
  return out;
}

// The candidates as multiples of 2^-16 (PRISMOID_FA_SCALE_ONE), as the CPU twin's candidate_scales gives them.
std::vector<uint32_t> candidate_numerators(double largest) {
  fastatlas::PackingOptions o;
  o.largest_scale = largest;
  o.smallest_scale = largest / 64.0;
  std::vector<uint32_t> out;
  for (double s : fastatlas::candidate_scales(o)) out.push_back(uint32_t(std::llround(s * PRISMOID_FA_SCALE_ONE)));
  return out;
}

void compute_barrier(VkCommandBuffer cmd) {
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, kShaderAccess,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                     kShaderAccess | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
}

uint32_t groups(uint32_t n) { return std::max(1u, (n + PRISMOID_FA_WORKGROUP - 1) / PRISMOID_FA_WORKGROUP); }

}  // namespace

std::string fastatlas_device_problem(const vk::Device& device) {
  return texture_space_device_problem(device, "FastAtlas");
}

FastAtlasPass::FastAtlasPass(const vk::Device& device, const SurfaceScene& scene, const FastAtlasSettings& settings)
    : device_(device),
      adjacency_(fastatlas::scene_adjacency(scene)),
      settings_(checked(device, settings)),
      set_layout_(vk::create_descriptor_set_layout(device, fastatlas_bindings())),
      layout_(make_layout(device, set_layout_.get())),
      shade_pipeline_(device, surface_rt_pipeline({"surface/fastatlas/shade.rgen", "surface/fastatlas/shade_unshadowed.rgen"}, layout_.get())),
      sort_by_root_(device, std::max<uint32_t>(1, uint32_t(adjacency_.neighbours.size()))),
      sort_by_height_(device, std::max<uint32_t>(1, uint32_t(adjacency_.neighbours.size()))),
      atlas_timer_(device, 8) {
  triangles_ = uint32_t(adjacency_.neighbours.size());
  vertices_ = uint32_t(adjacency_.mesh.vertex_count());
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), fastatlas_bindings());
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  const std::vector<gpu::FaTriangleGpu> table = triangle_table(adjacency_);
  triangle_table_ = vk::upload_buffer(device, std::as_bytes(std::span(table)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  const uint64_t t = std::max<uint32_t>(1, triangles_);
  parent_ = storage(device, t * 4);
  vertex_first_ = storage(device, std::max<uint64_t>(1, vertices_) * 4);
  boxes_ = storage(device, t * 16);
  keys_ = storage(device, t * 4);
  charts_ = storage(device, t * 4);
  placed_ = storage(device, t * 16);
  candidates_ = storage(device, PRISMOID_FA_MAX_CANDIDATES * 16);
  state_ = storage(device, sizeof(gpu::FaStateGpu), VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT);
  readback_ = vk::Buffer(device, sizeof(gpu::FaStateGpu), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  history_ = storage(device, 16);
  visible_ = storage(device, t * 4);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_FA_BINDING_VISIBLE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, visible_.get());
  prev_parent_ = storage(device, t * 4);
  prev_boxes_ = storage(device, t * 16);
  prev_placed_ = storage(device, t * 16);
  prev_state_ = storage(device, sizeof(gpu::FaStateGpu));
  prev_frame_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  const std::pair<uint32_t, const vk::Buffer*> previous[] = {{PRISMOID_FA_BINDING_PREV_PARENT, &prev_parent_},
                                                             {PRISMOID_FA_BINDING_PREV_BOXES, &prev_boxes_},
                                                             {PRISMOID_FA_BINDING_PREV_PLACED, &prev_placed_},
                                                             {PRISMOID_FA_BINDING_PREV_STATE, &prev_state_}};
  for (const auto& [binding, buffer] : previous)
    vk::write_buffer_descriptor(device, set_.set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer->get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_FA_BINDING_PREV_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, prev_frame_.get());
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_FA_BINDING_HISTORY, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, history_.get());
  set_settings(settings_);
  const VkDescriptorType s = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  const std::pair<uint32_t, const vk::Buffer*> buffers[] = {
      {PRISMOID_FA_BINDING_TRIANGLES, &triangle_table_}, {PRISMOID_FA_BINDING_PARENT, &parent_},
      {PRISMOID_FA_BINDING_VERTEX_FIRST, &vertex_first_}, {PRISMOID_FA_BINDING_BOXES, &boxes_},
      {PRISMOID_FA_BINDING_KEYS, &keys_},                 {PRISMOID_FA_BINDING_CHARTS, &charts_},
      {PRISMOID_FA_BINDING_PLACED, &placed_},             {PRISMOID_FA_BINDING_CANDIDATES, &candidates_},
      {PRISMOID_FA_BINDING_STATE, &state_}};
  for (const auto& [binding, buffer] : buffers) vk::write_buffer_descriptor(device, set_.set, binding, s, buffer->get());

  DepthThenVisiblePipelines visible = create_depth_then_visible(device, layout_.get(), "surface/fastatlas/visible.frag");
  depth_pipeline_ = std::move(visible.depth);
  visible_pipeline_ = std::move(visible.visible);
  claim_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/claim.comp", layout_.get());
  raster_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/raster.comp", layout_.get());
  raster_chunks_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/raster_chunks.comp", layout_.get());
  clear_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/clear.comp", layout_.get());
  copy_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/copy.comp", layout_.get());
  lookup_pipeline_ = create_fullscreen(device, layout_.get(), "surface/fastatlas/lookup.frag");
  vertices_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/vertices.comp", layout_.get());
  hook_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/hook.comp", layout_.get());
  boxes_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/boxes.comp", layout_.get());
  chart_list_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/chart_list.comp", layout_.get());
  height_keys_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/height_keys.comp", layout_.get());
  pack_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/pack.comp", layout_.get());
  seeds_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/seeds.comp", layout_.get());
  border_pipeline_ = vk::create_compute_pipeline(device, "surface/fastatlas/border.comp", layout_.get());
}

void FastAtlasPass::set_settings(const FastAtlasSettings& settings) {
  const FastAtlasSettings& s = checked(device_, settings);
  const bool resized = !id_atlas_.get() || s.atlas_width != settings_.atlas_width || s.atlas_height != settings_.atlas_height ||
                       s.raster_chunks != settings_.raster_chunks;
  const bool rescaled = scales_.empty() || s.shading_scale != settings_.shading_scale;
  const bool retemporal = !prev_color_.get() || (s.refresh > 0) != (settings_.refresh > 0);
  if (resized || rescaled || s.shadows != settings_.shadows || retemporal) last_frame_.reset();  // nothing of the last frame to reuse
  settings_ = s;
  if (rescaled) {
    scales_ = candidate_numerators(s.shading_scale);
    scales_buffer_ = vk::upload_buffer(device_, std::as_bytes(std::span(scales_)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    vk::write_buffer_descriptor(device_, set_.set, PRISMOID_FA_BINDING_SCALES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, scales_buffer_.get());
  }
  if (resized || retemporal) {
    // Temporal reuse keeps the last frame's colour atlas; without it a 1 x 1 stands in.
    const VkExtent2D pe = s.refresh > 0 ? VkExtent2D{s.atlas_width, s.atlas_height} : VkExtent2D{1, 1};
    prev_color_ = vk::Image(device_, pe, kAtlasColorFormat, VK_IMAGE_USAGE_STORAGE_BIT);
    vk::write_storage_image_descriptor(device_, set_.set, PRISMOID_FA_BINDING_PREV_COLOR, prev_color_.view());
    device_.submit_and_wait([&](VkCommandBuffer cmd) {
      vk::image_barrier(cmd, prev_color_.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                        VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    });
  }
  if (!resized) return;
  const VkExtent2D e{s.atlas_width, s.atlas_height};
  constexpr VkImageUsageFlags kAtlasUsage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  id_atlas_ = vk::Image(device_, e, kIdFormat, kAtlasUsage);
  depth_atlas_ = vk::Image(device_, e, kIdFormat, kAtlasUsage);
  color_atlas_ = vk::Image(device_, e, kAtlasColorFormat, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  front_ = storage(device_, uint64_t(PRISMOID_FA_MAX_CANDIDATES + 1) * s.atlas_width * 4);
  // Chunks for twice the atlas's area (large triangles overlap where charts fold over themselves);
  // past that the raster covers a triangle in one invocation (raster.comp), slower, not wrong.
  chunk_capacity_ = s.raster_chunks > 0 ? s.raster_chunks
                                        : std::max(4096u, uint32_t(2 * uint64_t(s.atlas_width) * s.atlas_height / (PRISMOID_FA_CHUNK * PRISMOID_FA_CHUNK)));
  chunks_ = storage(device_, uint64_t(chunk_capacity_) * 8);
  vk::write_buffer_descriptor(device_, set_.set, PRISMOID_FA_BINDING_RASTER_CHUNKS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, chunks_.get());
  vk::write_buffer_descriptor(device_, set_.set, PRISMOID_FA_BINDING_FRONT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, front_.get());
  vk::write_storage_image_descriptor(device_, set_.set, PRISMOID_FA_BINDING_ID_ATLAS, id_atlas_.view());
  vk::write_storage_image_descriptor(device_, set_.set, PRISMOID_FA_BINDING_COLOR_ATLAS, color_atlas_.view());
  vk::write_storage_image_descriptor(device_, set_.set, PRISMOID_FA_BINDING_DEPTH_ATLAS, depth_atlas_.view());
  // The atlases live in GENERAL; the ID and depth atlases start empty (each frame clears the rows
  // it and the last frame used), and no rows were used yet.
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    for (const vk::Image* image : {&color_atlas_, &id_atlas_, &depth_atlas_})
      vk::image_barrier(cmd, image->get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                        VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkImageSubresourceRange all{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    VkClearColorValue none{};
    none.uint32[0] = PRISMOID_FA_NONE;
    vkCmdClearColorImage(cmd, id_atlas_.get(), VK_IMAGE_LAYOUT_GENERAL, &none, 1, &all);
    const VkClearColorValue zero{};
    vkCmdClearColorImage(cmd, depth_atlas_.get(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &all);
    vkCmdFillBuffer(cmd, history_.get(), 0, VK_WHOLE_SIZE, 0u);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  });
  settings_.reuse = false;
}

void FastAtlasPass::bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const TextureSpaceTargets& targets) {
  if (scene.triangle_count != triangles_) throw std::invalid_argument("FastAtlasPass: the GPU scene is not the one its adjacency was built from");
  bound_.update(device_, set_.set, scene, tlas, targets.visibility, PRISMOID_FA_BINDING_VISIBILITY);
}

void FastAtlasPass::bind_compute(VkCommandBuffer cmd, VkPipeline pipeline, uint32_t pass) {
  gpu::FaPush push{};
  std::memcpy(&push, frame_push_.data(), sizeof(push));
  push.pass.x = pass;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), kPushStages, 0, sizeof(push), &push);
}

void FastAtlasPass::dispatch(VkCommandBuffer cmd, VkPipeline pipeline, uint32_t group_count, uint32_t pass) {
  bind_compute(cmd, pipeline, pass);
  vkCmdDispatch(cmd, group_count, 1, 1);
}

void FastAtlasPass::dispatch_indirect(VkCommandBuffer cmd, VkPipeline pipeline, VkDeviceSize state_offset, uint32_t pass) {
  bind_compute(cmd, pipeline, pass);
  vkCmdDispatchIndirect(cmd, state_.get(), state_offset);
}

void FastAtlasPass::record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, TextureSpaceTargets& targets,
                           const Camera& camera, vk::GpuTimer& timer) {
  validate(camera);
  bind(scene, tlas, targets);
  const VkExtent2D e = targets.extent;
  const gpu::SurfaceFrame frame = surface_frame(scene, camera, e, glm::dvec2(0.0));
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));
  gpu::FaPush push{};
  // Temporal reuse: between refreshes, where the last frame of these settings and image size exists.
  const bool same_image = last_frame_ && last_frame_->viewport.x == float(e.width) && last_frame_->viewport.y == float(e.height);
  temporal_ = settings_.refresh > 0 && !settings_.reuse && same_image && triangles_ < (1u << 24) &&
              frames_since_refresh_ + 1 < settings_.refresh;
  frames_since_refresh_ = temporal_ ? frames_since_refresh_ + 1 : 0;
  if (temporal_) prev_frame_.write(std::as_bytes(std::span(&*last_frame_, 1)));
  if (settings_.refresh > 0) last_frame_ = frame;
  const uint32_t flags = (settings_.shadows ? PRISMOID_FA_FLAG_SHADOWS : 0u) | (settings_.reuse ? PRISMOID_FA_FLAG_REUSE : 0u) |
                         (temporal_ ? PRISMOID_FA_FLAG_TEMPORAL : 0u);
  push.image = glm::uvec4(e.width, e.height, flags, triangles_);
  push.atlas = glm::uvec4(settings_.atlas_width, settings_.atlas_height, 1u, uint32_t(scales_.size()));
  const float near = float(camera.near_distance);
  push.pass = glm::uvec4(0u, vertices_, std::bit_cast<uint32_t>(near), chunk_capacity_);
  std::memcpy(frame_push_.data(), &push, sizeof(push));
  const PassBinding binding{layout_.get(), set_.set, kPushStages, std::as_bytes(std::span(&push, 1))};

  atlas_timer_.reset(cmd);
  // Everything per frame starts afresh; the colour atlas carries over (reuse).
  // The last frame's writes (its shading among them, which copy.comp reads) before anything of this one.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
  if (temporal_) {  // the last frame's maps, before this frame's start over
    for (const auto& [from, to] : {std::pair{&parent_, &prev_parent_}, {&boxes_, &prev_boxes_}, {&placed_, &prev_placed_}, {&state_, &prev_state_}}) {
      const VkBufferCopy all{0, 0, from->size()};
      vkCmdCopyBuffer(cmd, from->get(), to->get(), 1, &all);
    }
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                       VK_ACCESS_2_TRANSFER_WRITE_BIT);
  }
  vkCmdFillBuffer(cmd, targets.visibility.get(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, parent_.get(), 0, VK_WHOLE_SIZE, PRISMOID_FA_NONE);
  vkCmdFillBuffer(cmd, vertex_first_.get(), 0, VK_WHOLE_SIZE, PRISMOID_FA_NONE);
  vkCmdFillBuffer(cmd, boxes_.get(), 0, VK_WHOLE_SIZE, 0x7fffffffu);
  vkCmdFillBuffer(cmd, candidates_.get(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, front_.get(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, state_.get(), 0, VK_WHOLE_SIZE, 0u);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, kShaderStages, kShaderAccess);
  {
    vk::ScopedPass pass(timer, cmd, "pre-z + visibility");
    record_depth_then_visible(cmd, scene, targets.depth, e, depth_pipeline_.get(), visible_pipeline_.get(), binding);
  }
  {
    vk::ScopedPass pass(timer, cmd, "atlasing");
    compute_barrier(cmd);
    const uint32_t g = groups(triangles_);
    {
      vk::ScopedPass step(atlas_timer_, cmd, "charts");
      dispatch(cmd, vertices_pipeline_.get(), g, 0);
      compute_barrier(cmd);
      dispatch(cmd, hook_pipeline_.get(), g, 0);
      compute_barrier(cmd);
    }
    {
      vk::ScopedPass step(atlas_timer_, cmd, "boxes");
      dispatch(cmd, boxes_pipeline_.get(), g, 0);
      compute_barrier(cmd);
      dispatch(cmd, chart_list_pipeline_.get(), g, 0);
      compute_barrier(cmd);
    }
    {
      vk::ScopedPass step(atlas_timer_, cmd, "order");
      const uint32_t most = std::max(1u, triangles_);
      sort_by_root_.record_indirect(cmd, keys_, charts_, state_, 0, most);
      dispatch(cmd, height_keys_pipeline_.get(), g, 0);
      compute_barrier(cmd);
      sort_by_height_.record_indirect(cmd, keys_, charts_, state_, 0, most);
    }
    {
      vk::ScopedPass step(atlas_timer_, cmd, "packing");
      dispatch(cmd, pack_pipeline_.get(), uint32_t(scales_.size()), 0);
      compute_barrier(cmd);
      dispatch(cmd, pack_pipeline_.get(), 1, 1);
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kShaderAccess, kShaderStages | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                         kShaderAccess | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
    }
    {
      vk::ScopedPass step(atlas_timer_, cmd, "id raster");
      dispatch_indirect(cmd, clear_pipeline_.get(), offsetof(gpu::FaStateGpu, clear));
      compute_barrier(cmd);
      bind_compute(cmd, claim_pipeline_.get(), 0);
      vkCmdDispatch(cmd, (e.width + 15) / 16, (e.height + 15) / 16, 1);
      compute_barrier(cmd);
      // Depth, then IDs (fa_raster.glsl): each a pass over the small triangles and one over the
      // large ones' chunks, in a fixed number of workgroups that walk the chunk list.
      const uint32_t chunk_groups = std::min(1024u, chunk_capacity_);
      for (uint32_t raster_pass : {0u, 1u}) {
        dispatch_indirect(cmd, raster_pipeline_.get(), offsetof(gpu::FaStateGpu, raster), raster_pass);
        compute_barrier(cmd);
        dispatch(cmd, raster_chunks_pipeline_.get(), chunk_groups, raster_pass);
        compute_barrier(cmd);
      }
    }
    {
      vk::ScopedPass step(atlas_timer_, cmd, "borders");
      if (temporal_) {  // the last frame's colour rows, before shading writes over them
        dispatch_indirect(cmd, copy_pipeline_.get(), offsetof(gpu::FaStateGpu, copy));
      }
      dispatch(cmd, seeds_pipeline_.get(), g, 0);
      compute_barrier(cmd);
      dispatch_indirect(cmd, border_pipeline_.get(), offsetof(gpu::FaStateGpu, dispatch));
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, kShaderAccess, kShaderStages | VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT,
                         kShaderAccess | VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT);
    }
  }
  record_indirect_shading(cmd, timer, shade_pipeline_, settings_.shadows ? 0 : 1, binding,
                          state_.device_address() + offsetof(gpu::FaStateGpu, trace));
  {
    vk::ScopedPass pass(timer, cmd, "lookup");
    record_fullscreen(cmd, targets.color, e, lookup_pipeline_.get(), binding);
  }
  record_state_readback(cmd, state_, readback_, sizeof(gpu::FaStateGpu));
}

FastAtlasCounters FastAtlasPass::read_counters() const {
  const auto s = read_mapped<gpu::FaStateGpu>(readback_);
  FastAtlasCounters c;
  c.charts = s.charts.x;
  c.candidate = s.charts.y;
  c.fits = s.charts.z == 1u;
  c.rows_used = s.charts.w;
  c.scale = c.fits && c.candidate < scales_.size() ? double(scales_[c.candidate]) / PRISMOID_FA_SCALE_ONE : 0.0;
  c.shaded_texels = s.trace.w;
  c.reused_texels = s.copy.w;
  c.temporal = temporal_;
  c.border_texels = s.dispatch.w;
  c.hole_pixels = s.counts.y;
  c.visible_triangles = s.counts.x;
  if (s.stretch.y > 0) {
    const double sum = (double(s.stretch.w) * 4294967296.0 + double(s.stretch.x)) / 4096.0;
    c.stretch_l2 = std::sqrt(sum / double(s.stretch.y));
    c.stretch_linf = double(std::bit_cast<float>(s.stretch.z));
  }
  const uint64_t texels = uint64_t(settings_.atlas_width) * settings_.atlas_height;
  c.atlas_bytes = texels * (4 + 4 + 16) + history_.size() + visible_.size() +
                  (settings_.refresh > 0 ? texels * 16 + prev_parent_.size() + prev_boxes_.size() + prev_placed_.size() : 0) + parent_.size() + vertex_first_.size() + boxes_.size() + keys_.size() + charts_.size() +
                  placed_.size() + front_.size() + chunks_.size() + triangle_table_.size() + sort_by_root_.bytes() + sort_by_height_.bytes();
  return c;
}

namespace {

template <typename T>
std::vector<T> as_vector(const std::vector<std::byte>& bytes, size_t count) {
  std::vector<T> out(count);
  std::memcpy(out.data(), bytes.data(), count * sizeof(T));
  return out;
}

}  // namespace

std::vector<uint32_t> FastAtlasPass::read_parent() const { return as_vector<uint32_t>(read_device_buffer(device_, parent_), triangles_); }
std::vector<glm::ivec4> FastAtlasPass::read_boxes() const { return as_vector<glm::ivec4>(read_device_buffer(device_, boxes_), triangles_); }
std::vector<glm::uvec4> FastAtlasPass::read_placed() const { return as_vector<glm::uvec4>(read_device_buffer(device_, placed_), triangles_); }
std::vector<uint32_t> FastAtlasPass::read_sorted_charts() const {
  return as_vector<uint32_t>(read_device_buffer(device_, charts_), read_counters().charts);
}

std::vector<uint32_t> FastAtlasPass::read_id_atlas() const {
  std::vector<uint32_t> out(size_t(settings_.atlas_width) * settings_.atlas_height);
  vk::read_image(device_, id_atlas_, sizeof(uint32_t), std::as_writable_bytes(std::span(out)), VK_IMAGE_LAYOUT_GENERAL);
  return out;
}

std::vector<glm::vec4> FastAtlasPass::read_color_atlas() const {
  std::vector<glm::vec4> out(size_t(settings_.atlas_width) * settings_.atlas_height);
  vk::read_image(device_, color_atlas_, sizeof(glm::vec4), std::as_writable_bytes(std::span(out)), VK_IMAGE_LAYOUT_GENERAL);
  return out;
}

FastAtlasImage render_fastatlas(const vk::Device& device, FastAtlasPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                                const Camera& camera, VkExtent2D extent) {
  return render_texture_space_frame<FastAtlasImage>(device, pass, scene, tlas, camera, extent);
}

}  // namespace prismoid::surface
