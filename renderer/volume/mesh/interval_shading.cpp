#include "renderer/volume/mesh/interval_shading.hpp"

#include <algorithm>
#include <array>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/timer.hpp"
#include "renderer/volume/interval_march.hpp"
#include "renderer/volume/tetlets.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "scene/tet_mesh.hpp"
#include "shaders/shared/volume.h"

namespace prismoid::volume {

namespace {

// The accumulation targets' formats (create_targets in volume_inputs.cpp makes them).
constexpr VkFormat kOpticalDepthFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kEmissionFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

constexpr VkQueryPipelineStatisticFlags kCountedStatistics =
    VK_QUERY_PIPELINE_STATISTIC_CLIPPING_INVOCATIONS_BIT | VK_QUERY_PIPELINE_STATISTIC_FRAGMENT_SHADER_INVOCATIONS_BIT;

const std::array<vk::DescriptorBinding, 15> kMeshBindings = {{
    {PRISMOID_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT | VK_SHADER_STAGE_FRAGMENT_BIT},
    {PRISMOID_BINDING_POSITIONS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_TETS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_CELL_SIGMA, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_POINT_SIGMA, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_CELL_SCALAR, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_POINT_SCALAR, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_ORDER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_PREINTEGRATED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT},
    {PRISMOID_BINDING_TRANSFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT},
    {PRISMOID_BINDING_TETLETS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_TETLET_POINTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_TETLET_CELLS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_MESH_BIT_EXT},
    {PRISMOID_BINDING_FIELD_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT},
    {PRISMOID_BINDING_DEPTH_LIMIT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_FRAGMENT_BIT},
}};

template <typename T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

}  // namespace

IntervalShadingPass::IntervalShadingPass(const vk::Device& device) : device_(device) {
  const auto& caps = device.capabilities();
  if (caps.max_mesh_output_vertices < PRISMOID_CELL_MAX_VERTICES || caps.max_mesh_output_primitives < PRISMOID_CELL_MAX_TRIANGLES)
    throw vk::NoSuitableDevice(caps.name + " allows " + std::to_string(caps.max_mesh_output_vertices) + " vertices / " +
                               std::to_string(caps.max_mesh_output_primitives) + " primitives per mesh workgroup; interval shading needs " +
                               std::to_string(PRISMOID_CELL_MAX_VERTICES) + " / " + std::to_string(PRISMOID_CELL_MAX_TRIANGLES));
  mesh_set_layout_ = vk::create_descriptor_set_layout(device, kMeshBindings);
  VkDescriptorSetLayout mesh_sets[] = {mesh_set_layout_.get()};
  VkPushConstantRange mesh_push{VK_SHADER_STAGE_MESH_BIT_EXT, 0, sizeof(uint32_t)};
  mesh_layout_ = vk::create_pipeline_layout(device, mesh_sets, std::span(&mesh_push, 1));
  mesh_set_ = vk::allocate_descriptor_set(device, mesh_set_layout_.get(), kMeshBindings);

  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, mesh_set_.set, PRISMOID_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  if (caps.pipeline_statistics) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    info.queryCount = 1;
    info.pipelineStatistics = kCountedStatistics;
    VkQueryPool pool;
    vk::check(vkCreateQueryPool(device.get(), &info, nullptr, &pool), "vkCreateQueryPool");
    statistics_ = vk::UniqueQueryPool(device.get(), pool);
  }
  const glm::vec4 zero(0.0f);
  stub_ = vk::upload_buffer(device, std::as_bytes(std::span(&zero, 1)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  bind_order(nullptr);
  for (uint32_t binding : {PRISMOID_BINDING_TETLETS, PRISMOID_BINDING_TETLET_POINTS, PRISMOID_BINDING_TETLET_CELLS})
    vk::write_buffer_descriptor(device, mesh_set_.set, binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stub_.get());
}

IntervalShadingPass::DrawCounts IntervalShadingPass::read_counts() const {
  DrawCounts counts;
  if (statistics_.get() == VK_NULL_HANDLE || !counted_) return counts;
  uint64_t values[2] = {0, 0};  // in the order of the bits: clipping invocations, fragment invocations
  vk::check(vkGetQueryPoolResults(device_.get(), statistics_.get(), 0, 1, sizeof(values), values, sizeof(values),
                                  VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
            "vkGetQueryPoolResults");
  counts.primitives = values[0];
  counts.fragments = values[1];
  return counts;
}

uint32_t max_tetlet_size(const vk::Device& device) {
  const auto& caps = device.capabilities();
  uint32_t best = 1;
  for (uint32_t size : kTetletSizes)
    if (size * PRISMOID_CELL_MAX_VERTICES <= caps.max_mesh_output_vertices &&
        size * PRISMOID_CELL_MAX_TRIANGLES <= caps.max_mesh_output_primitives)
      best = size;
  return best;
}

IntervalShadingPass::PipelineKind IntervalShadingPass::pipeline_kind(const ResolveSettings& settings) {
  if (settings.march.enabled) {
    if (settings.quantity == Quantity::Color) return PipelineKind::MarchColor;
    if (settings.quantity == Quantity::Isosurface) return PipelineKind::Isosurface;
    return PipelineKind::MarchDepth;
  }
  return settings.quantity == Quantity::Color ? PipelineKind::Emission : PipelineKind::OpticalDepth;
}

VkPipeline IntervalShadingPass::pipeline(uint32_t tetlet_size, PipelineKind kind, bool shared_vertices) {
  auto& slot = pipelines_[{tetlet_size, kind, shared_vertices}];
  if (slot.get() != VK_NULL_HANDLE) return slot.get();
  const std::string mesh_shader = shared_vertices ? "volume/interval_s" + std::to_string(tetlet_size) + ".mesh"
                                  : tetlet_size == PRISMOID_MAX_TETS_PER_WORKGROUP
                                      ? std::string("volume/interval.mesh")
                                      : "volume/interval_w" + std::to_string(tetlet_size) + ".mesh";
  vk::MeshPipelineDesc desc;
  desc.mesh_shader = mesh_shader;
  desc.layout = mesh_layout_.get();
  switch (kind) {
    case PipelineKind::OpticalDepth:  // sigma * length, summed
    case PipelineKind::MarchDepth:
      desc.fragment_shader = kind == PipelineKind::OpticalDepth ? "volume/optical_depth.frag" : "volume/march.frag";
      desc.color_formats = {kOpticalDepthFormat};
      desc.blend = vk::BlendMode::Additive;
      break;
    case PipelineKind::Emission:  // premultiplied colour, composited front to back
    case PipelineKind::MarchColor:
      desc.fragment_shader = kind == PipelineKind::Emission ? "volume/emission.frag" : "volume/march.frag";
      desc.color_formats = {kEmissionFormat};
      desc.blend = vk::BlendMode::FrontToBack;
      break;
    case PipelineKind::Isosurface:  // the nearest hit wins the depth test, in any draw order
      desc.fragment_shader = "volume/isosurface.frag";
      desc.color_formats = {kEmissionFormat};
      desc.blend = vk::BlendMode::None;
      desc.depth_format = VK_FORMAT_D32_SFLOAT;
      desc.depth_compare = VK_COMPARE_OP_GREATER;  // near / depth: greater is nearer
      break;
  }
  slot = vk::create_mesh_pipeline(device_, desc);
  return slot.get();
}

GpuTetlets upload_tetlets(const vk::Device& device, const TetMesh& mesh, uint32_t tetlet_size) {
  const Tetlets t = build_tetlets(mesh, tetlet_size, PRISMOID_TETLET_MAX_POINTS);
  GpuTetlets gpu;
  gpu.count = static_cast<uint32_t>(t.headers.size());
  gpu.max_cells = tetlet_size;
  gpu.points_per_cell = t.points_per_cell();
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  auto nonempty = [](auto v) {
    if (v.empty()) v.resize(1);
    return v;
  };
  gpu.headers = vk::upload_buffer(device, bytes_of(nonempty(t.headers)), usage);
  gpu.points = vk::upload_buffer(device, bytes_of(nonempty(t.points)), usage);
  gpu.cells = vk::upload_buffer(device, bytes_of(nonempty(t.cells)), usage);
  return gpu;
}

void IntervalShadingPass::bind_tetlets(const GpuTetlets* tetlets) {
  if (!tetlets) return;
  const std::array<uint64_t, 3> key{tetlets->headers.serial(), tetlets->points.serial(), tetlets->cells.serial()};
  if (key == bound_tetlets_) return;
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_TETLETS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, tetlets->headers.get());
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_TETLET_POINTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, tetlets->points.get());
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_TETLET_CELLS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, tetlets->cells.get());
  bound_tetlets_ = key;
}

void IntervalShadingPass::bind_order(const vk::Buffer* order) {
  const vk::Buffer& buffer = order ? *order : stub_;
  if (buffer.serial() == bound_order_) return;
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_ORDER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffer.get());
  bound_order_ = buffer.serial();
}

void IntervalShadingPass::prepare(const ResolveSettings& settings) {
  check_workgroup_settings(settings);
  if (settings.tetlet_size > max_tetlet_size(device_))
    throw InputError(setting("tetlet-size"), device_.capabilities().name + " fits at most " + std::to_string(max_tetlet_size(device_)) +
                                          " near-clipped cells' proxies in one mesh workgroup");
  pipeline(settings.tetlet_size, pipeline_kind(settings), settings.shared_vertices);  // created here, outside any frame
}

void IntervalShadingPass::bind_mesh(const GpuTetMesh& mesh) {
  const std::array<uint64_t, 6> key{mesh.positions.serial(),  mesh.tets.serial(),        mesh.cell_sigma.serial(),
                                    mesh.point_sigma.serial(), mesh.cell_scalar.serial(), mesh.point_scalar.serial()};
  if (key == bound_mesh_) return;
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_POSITIONS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, mesh.positions.get());
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_TETS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, mesh.tets.get());
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_CELL_SIGMA, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, mesh.cell_sigma.get());
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_POINT_SIGMA, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, mesh.point_sigma.get());
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_CELL_SCALAR, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, mesh.cell_scalar.get());
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_POINT_SCALAR, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, mesh.point_scalar.get());
  bound_mesh_ = key;
}

void IntervalShadingPass::bind_inputs(const VolumeInputs& inputs) {
  const std::array<const vk::Buffer*, 4> buffers{&inputs.transfer_buffer(), &inputs.table_buffer(), &inputs.grid_buffer(),
                                                 &inputs.depth_limit_buffer()};
  const std::array<uint32_t, 4> bindings{PRISMOID_BINDING_TRANSFER, PRISMOID_BINDING_PREINTEGRATED, PRISMOID_BINDING_FIELD_GRID,
                                         PRISMOID_BINDING_DEPTH_LIMIT};
  for (size_t i = 0; i < buffers.size(); ++i) {
    if (buffers[i]->serial() == bound_inputs_[i]) continue;
    vk::write_buffer_descriptor(device_, mesh_set_.set, bindings[i], VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffers[i]->get());
    bound_inputs_[i] = buffers[i]->serial();
  }
}

void IntervalShadingPass::record(VkCommandBuffer cmd, const GpuTetMesh& mesh, const VolumeInputs& inputs, VolumeTargets& targets,
                                 const Camera& camera, const ResolveSettings& settings, vk::GpuTimer& timer, const vk::Buffer* order,
                                 const GpuTetlets* tetlets) {
  validate(camera);
  const bool emission = settings.quantity == Quantity::Color;
  const bool march = settings.march.enabled, isosurface = settings.quantity == Quantity::Isosurface;
  if (isosurface && !march) throw std::logic_error("IntervalShadingPass: an isosurface needs marching (settings.march)");
  inputs.check_ready(settings);
  bind_mesh(mesh);
  bind_inputs(inputs);
  bind_order(order);
  if (tetlets && (order || tetlets->max_cells != settings.tetlet_size))
    throw std::logic_error("IntervalShadingPass: tetlets draw in their own order, built for their own size");
  bind_tetlets(tetlets);
  const VkExtent2D e = targets.extent;
  const gpu::FrameUniforms frame = inputs.frame_uniforms(mesh, camera, e, settings, order != nullptr);
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));

  const bool to_emission = emission || isosurface;
  const vk::Image& target = to_emission ? targets.emission : targets.optical_depth;
  {
    vk::ScopedPass pass(timer, cmd, interval_pass_name(settings));
    vk::image_barrier(cmd, target.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT);
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = target.view();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, e};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    if (isosurface) {
      depth = begin_isosurface_depth(cmd, targets);
      rendering.pDepthAttachment = &depth;
    }
    const bool count = statistics_.get() != VK_NULL_HANDLE;
    if (count) vkCmdResetQueryPool(cmd, statistics_.get(), 0, 1);
    vkCmdBeginRendering(cmd, &rendering);
    if (count) vkCmdBeginQuery(cmd, statistics_.get(), 0, 0);
    VkViewport viewport{0.0f, 0.0f, float(e.width), float(e.height), 0.0f, 1.0f};
    VkRect2D scissor{{0, 0}, e};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    if (mesh.tet_count > 0) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                        pipeline(settings.tetlet_size, pipeline_kind(settings), tetlets != nullptr));
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, mesh_layout_.get(), 0, 1, &mesh_set_.set, 0, nullptr);
      const uint32_t groups = tetlets ? tetlets->count : (mesh.tet_count + settings.tetlet_size - 1) / settings.tetlet_size;
      // One draw launches at most maxMeshWorkGroupCount[0] (and the total count) workgroups;
      // consecutive draws keep the primitive order a sorted frame composites in.
      const auto& caps = device_.capabilities();
      const uint32_t per_draw = std::max<uint32_t>(1, std::min(caps.max_mesh_groups_x, caps.max_mesh_groups_total));
      for (uint32_t first = 0; first < groups; first += per_draw) {
        vkCmdPushConstants(cmd, mesh_layout_.get(), VK_SHADER_STAGE_MESH_BIT_EXT, 0, sizeof(first), &first);
        device_.cmd_draw_mesh_tasks(cmd, std::min(per_draw, groups - first), 1, 1);
      }
    }
    if (count) vkCmdEndQuery(cmd, statistics_.get(), 0);
    counted_ = counted_ || count;
    vkCmdEndRendering(cmd);
  }
}

}  // namespace prismoid::volume
