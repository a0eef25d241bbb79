#include "renderer/volume/interval_shading.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <glm/geometric.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/timer.hpp"
#include "renderer/volume/float_limits.hpp"
#include "renderer/volume/tetlets.hpp"
#include "renderer/volume/interval_march.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"
#include "shaders/shared/volume.h"

namespace prismoid::volume {

namespace {

constexpr VkFormat kOpticalDepthFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kQuantityFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kDisplayFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kEmissionFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

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

const std::array<vk::DescriptorBinding, 4> kResolveBindings = {{
    {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
    {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
    {2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
    {3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
}};

template <typename T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

glm::mat4 to_float(const glm::dmat4& m) { return glm::mat4(m); }

}  // namespace

GpuTetMesh upload(const vk::Device& device, const TetMesh& mesh) {
  validate(mesh);
  GpuTetMesh gpu;
  const Bounds bounds = bounds_of(mesh);
  gpu.origin = bounds.center();
  gpu.extinction_cap = extinction_cap(glm::length(bounds.max - bounds.min));
  gpu.radius = 0.5 * glm::length(bounds.max - bounds.min);
  auto capped = [&](const std::vector<double>& v) {
    std::vector<float> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) out[i] = float(std::min(v[i], gpu.extinction_cap));
    if (out.empty()) out.push_back(0.0f);
    return out;
  };
  gpu.tet_count = static_cast<uint32_t>(mesh.tets.size());
  std::vector<glm::vec4> positions;
  positions.reserve(mesh.points.size());
  for (const auto& p : mesh.points) positions.emplace_back(glm::vec3(p - gpu.origin), 1.0f);
  std::vector<glm::uvec4> tets;
  tets.reserve(mesh.tets.size());
  for (const auto& t : mesh.tets) tets.emplace_back(t[0], t[1], t[2], t[3]);
  const std::vector<float> sigma = capped(mesh.cell_extinction);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu.positions = vk::upload_buffer(device, bytes_of(positions), usage);
  gpu.tets = vk::upload_buffer(device, bytes_of(tets), usage);
  gpu.cell_sigma = vk::upload_buffer(device, bytes_of(sigma), usage);
  gpu.linear = mesh.linear_extinction();
  // Storage buffers cannot be empty: absent arrays get one unused value.
  auto floats = [](const std::vector<double>& v) {
    return v.empty() ? std::vector<float>{0.0f} : std::vector<float>(v.begin(), v.end());
  };
  gpu.point_sigma = vk::upload_buffer(device, bytes_of(capped(mesh.point_extinction)), usage);
  gpu.scalar_per_point = !mesh.point_scalars.empty();
  gpu.has_scalars = gpu.scalar_per_point || !mesh.cell_scalars.empty();
  gpu.cell_scalar = vk::upload_buffer(device, bytes_of(floats(mesh.cell_scalars)), usage);
  gpu.point_scalar = vk::upload_buffer(device, bytes_of(floats(mesh.point_scalars)), usage);
  const auto& field = gpu.scalar_per_point ? mesh.point_scalars : mesh.cell_scalars;
  if (!field.empty()) {
    const auto [lo, hi] = std::minmax_element(field.begin(), field.end());
    gpu.scalar_min = *lo;
    gpu.scalar_max = *hi;
  }
  for (const auto& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        gpu.longest_edge = std::max(gpu.longest_edge, glm::distance(mesh.points[t[i]], mesh.points[t[j]]));
  return gpu;
}

VolumeTargets create_targets(const vk::Device& device, VkExtent2D extent) {
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT | VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT;
  if ((device.format_properties(kOpticalDepthFormat).optimalTilingFeatures & need) != need)
    throw vk::NoSuitableDevice(device.capabilities().name + " cannot blend into and read R32_SFLOAT images");
  if ((device.format_properties(kEmissionFormat).optimalTilingFeatures & need) != need)
    throw vk::NoSuitableDevice(device.capabilities().name + " cannot blend into and read R32G32B32A32_SFLOAT images");
  VolumeTargets t;
  t.extent = extent;
  t.emission = vk::Image(device, extent, kEmissionFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.optical_depth = vk::Image(device, extent, kOpticalDepthFormat,
                              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT);
  t.quantity = vk::Image(device, extent, kQuantityFormat, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.display = vk::Image(device, extent, kDisplayFormat, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.depth = vk::Image(device, extent, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT);
  return t;
}

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

  resolve_set_layout_ = vk::create_descriptor_set_layout(device, kResolveBindings);
  VkDescriptorSetLayout resolve_sets[] = {resolve_set_layout_.get()};
  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::ResolvePush)};
  resolve_layout_ = vk::create_pipeline_layout(device, resolve_sets, std::span(&push, 1));
  resolve_pipeline_ = vk::create_compute_pipeline(device, "volume/resolve.comp", resolve_layout_.get());
  resolve_set_ = vk::allocate_descriptor_set(device, resolve_set_layout_.get(), kResolveBindings);

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
  vk::write_buffer_descriptor(device, mesh_set_.set, PRISMOID_BINDING_PREINTEGRATED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stub_.get());
  vk::write_buffer_descriptor(device, mesh_set_.set, PRISMOID_BINDING_TRANSFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, stub_.get());
  for (uint32_t binding : {PRISMOID_BINDING_TETLETS, PRISMOID_BINDING_TETLET_POINTS, PRISMOID_BINDING_TETLET_CELLS,
                           PRISMOID_BINDING_FIELD_GRID, PRISMOID_BINDING_DEPTH_LIMIT})
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

void IntervalShadingPass::prepare(const GpuTetMesh& mesh, const ResolveSettings& settings, bool mesh_pipeline) {
  validate_march(mesh, settings);
  if (std::find(kTetletSizes.begin(), kTetletSizes.end(), settings.tetlet_size) == kTetletSizes.end())
    throw InputError("--tetlet-size", "must be 1, 4, 8 or 16 cells per mesh workgroup");
  // The mesh shader's limits bind only the frames it draws.
  if (mesh_pipeline && settings.tetlet_size > max_tetlet_size(device_))
    throw InputError("--tetlet-size", device_.capabilities().name + " fits at most " + std::to_string(max_tetlet_size(device_)) +
                                          " near-clipped cells' proxies in one mesh workgroup");
  if (settings.shared_vertices && settings.tetlet_size == 1)
    throw InputError("--shared-vertices", "groups several cells per workgroup: use --tetlet-size 4, 8 or 16");
  if (mesh_pipeline) pipeline(settings.tetlet_size, pipeline_kind(settings), settings.shared_vertices);  // created here, outside any frame
  if (settings.march.enabled && settings.march.field.kind == FieldKind::Grid) upload_grid(settings.march.field.grid);
  // Where the rays end (opaque geometry), written while no frame is in flight; its size is the
  // frame's, checked by the caller (frame_renderer.cpp).
  if (settings.depth_limit) {
    const std::vector<float>& limit = *settings.depth_limit;
    const VkDeviceSize bytes = std::max<VkDeviceSize>(limit.size() * sizeof(float), sizeof(float));
    if (depth_limit_.size() < bytes) depth_limit_ = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::HostVisible);
    depth_limit_.write(std::as_bytes(std::span(limit)));
    vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_DEPTH_LIMIT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, depth_limit_.get());
  }
  if (settings.quantity != Quantity::Color) return;
  if (!mesh.has_scalars) throw InputError("color", "the dataset has no scalar field for the transfer function (choose one with --array NAME)");
  validate(settings.transfer);
  if (settings.preintegration_size == 1 || settings.preintegration_size > 256)
    throw InputError("--preintegration-size", "must be 0 (exact integration) or between 2 and 256 texels per axis");
}

namespace {

bool same_breakpoints(const std::vector<TfSample>& a, const std::vector<TfSample>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const TfSample& x, const TfSample& y) {
           return x.x == y.x && x.rgb == y.rgb && x.sigma == y.sigma;
         });
}

double table_length(const GpuTetMesh& mesh) { return mesh.longest_edge > 0.0 ? mesh.longest_edge : 1.0; }

}  // namespace

bool IntervalShadingPass::transfer_current(const GpuTetMesh& mesh, const ResolveSettings& settings) const {
  if (tf_buffer_.get() == VK_NULL_HANDLE || !same_breakpoints(breakpoints(settings.transfer), table_tf_)) return false;
  return settings.preintegration_size == 0 ||
         (table_buffer_.get() != VK_NULL_HANDLE && table_.size == settings.preintegration_size && table_.max_length == table_length(mesh));
}

double IntervalShadingPass::upload_transfer(const GpuTetMesh& mesh, const ResolveSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<TfSample> tf = breakpoints(settings.transfer);
  const double max_length = table_length(mesh);
  const bool same_tf = same_breakpoints(tf, table_tf_);
  const bool table_wanted = settings.preintegration_size > 0;
  const bool same_table = !table_wanted || (table_buffer_.get() != VK_NULL_HANDLE && same_tf &&
                                            table_.size == settings.preintegration_size && table_.max_length == max_length);
  device_.wait_idle();  // the old buffers may still be read by a frame in flight
  if (!same_tf || tf_buffer_.get() == VK_NULL_HANDLE) {
    std::vector<glm::vec4> packed;
    for (const TfSample& t : tf) {
      packed.emplace_back(float(t.x), float(std::min(t.sigma, mesh.extinction_cap)), 0.0f, 0.0f);
      packed.emplace_back(glm::vec3(t.rgb), 0.0f);
    }
    tf_buffer_ = vk::upload_buffer(device_, bytes_of(packed), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_TRANSFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, tf_buffer_.get());
  }
  if (!same_table) {
    table_ = build_preintegration_table(tf, settings.preintegration_size, max_length);
    table_buffer_ = vk::upload_buffer(device_, bytes_of(table_.texels), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_PREINTEGRATED, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                table_buffer_.get());
  }
  table_tf_ = std::move(tf);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void IntervalShadingPass::upload_grid(const std::shared_ptr<const SampledGrid>& grid) {
  if (grid == grid_) return;
  const uint64_t bytes = uint64_t(grid->values.size()) * sizeof(float);
  if (bytes > device_.capabilities().max_storage_buffer_range)
    throw InputError(grid->name, "its " + std::to_string(grid->values.size()) + " samples exceed the " +
                                     std::to_string(device_.capabilities().max_storage_buffer_range) +
                                     " bytes one storage buffer may hold on " + device_.capabilities().name);
  device_.wait_idle();  // the old samples may still be read by a frame in flight
  grid_buffer_ = vk::upload_buffer(device_, bytes_of(grid->values), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  vk::write_buffer_descriptor(device_, mesh_set_.set, PRISMOID_BINDING_FIELD_GRID, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, grid_buffer_.get());
  grid_ = grid;
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

void IntervalShadingPass::bind_targets(const VolumeTargets& targets) {
  const std::array<uint64_t, 4> key{targets.optical_depth.serial(), targets.display.serial(), targets.quantity.serial(),
                                    targets.emission.serial()};
  if (key == bound_targets_) return;
  vk::write_storage_image_descriptor(device_, resolve_set_.set, 0, targets.optical_depth.view());
  vk::write_storage_image_descriptor(device_, resolve_set_.set, 1, targets.display.view());
  vk::write_storage_image_descriptor(device_, resolve_set_.set, 2, targets.quantity.view());
  vk::write_storage_image_descriptor(device_, resolve_set_.set, 3, targets.emission.view());
  bound_targets_ = key;
}

gpu::FrameUniforms IntervalShadingPass::frame_uniforms(const GpuTetMesh& mesh, const Camera& camera, VkExtent2D e,
                                                      const ResolveSettings& settings, bool ordered) const {
  const bool emission = settings.quantity == Quantity::Color;
  const bool march = settings.march.enabled;
  const bool use_table = settings.preintegration_size > 0;
  const double aspect = double(e.width) / double(e.height);
  const glm::dmat4 proj = projection_matrix(camera, aspect);

  gpu::FrameUniforms frame{};
  const glm::dmat4 view = view_matrix(camera, mesh.origin);
  frame.view = to_float(view);
  frame.projection = to_float(proj);
  frame.viewport = glm::vec4(float(e.width), float(e.height), 1.0f / float(e.width), 1.0f / float(e.height));
  // The near plane's depth minus the mesh origin's (view[3].z is minus that depth), in double:
  // the interval stages clip relative to each cell's reference point, at any distance from the eye.
  frame.ray_scale = glm::vec4(float(1.0 / proj[0][0]), float(1.0 / proj[1][1]), float(camera.near_distance),
                              float(camera.near_distance + view[3][2]));
  // Marching draws every cell (the mesh shader's emission path: no cell is culled by its
  // extinction, near-clipped pieces in order) and ignores the proxy's linear field.
  const bool per_point = emission || march ? mesh.scalar_per_point : mesh.linear;
  frame.counts = glm::uvec4(mesh.tet_count, per_point ? 1u : 0u,
                            emission || march ? PRISMOID_INTEGRAND_EMISSION : PRISMOID_INTEGRAND_OPTICAL_DEPTH, ordered ? 1u : 0u);
  const TransferFunction& tf = settings.transfer;
  const ScalarMapping mapping = scalar_mapping(tf);
  frame.transfer = glm::vec4(float(mapping.scale), float(mapping.offset), float(table_.max_length), float(table_.size));
  frame.options = glm::uvec4(uint32_t(table_tf_.size()), use_table ? PRISMOID_SEGMENTS_TABLE : PRISMOID_SEGMENTS_EXACT,
                             settings.depth_limit ? 1u : 0u, 0u);
  if (march) fill_march_uniforms(frame, settings, camera, mesh.origin, mesh.extinction_cap);
  return frame;
}

void IntervalShadingPass::intervals_drawn_by_compute() {
  intervals_recorded_ = true;
  intervals_by_compute_ = true;
}

void IntervalShadingPass::record(VkCommandBuffer cmd, const GpuTetMesh& mesh, VolumeTargets& targets, const Camera& camera,
                                 const ResolveSettings& settings, vk::GpuTimer& timer, const vk::Buffer* order,
                                 const GpuTetlets* tetlets) {
  record_intervals(cmd, mesh, targets, camera, settings, timer, order, tetlets);
  record_resolve(cmd, targets, settings, timer);
}

void IntervalShadingPass::record_intervals(VkCommandBuffer cmd, const GpuTetMesh& mesh, VolumeTargets& targets,
                                           const Camera& camera, const ResolveSettings& settings, vk::GpuTimer& timer,
                                           const vk::Buffer* order, const GpuTetlets* tetlets) {
  validate(camera);
  const bool emission = settings.quantity == Quantity::Color;
  const bool march = settings.march.enabled, isosurface = settings.quantity == Quantity::Isosurface;
  if (isosurface && !march) throw std::logic_error("IntervalShadingPass: an isosurface needs marching (settings.march)");
  const bool use_table = settings.preintegration_size > 0;
  if (emission && (tf_buffer_.get() == VK_NULL_HANDLE || (use_table && table_buffer_.get() == VK_NULL_HANDLE)))
    throw std::logic_error("IntervalShadingPass: colour needs prepare() before record()");
  if (march && settings.march.field.kind == FieldKind::Grid && settings.march.field.grid != grid_)
    throw std::logic_error("IntervalShadingPass: a grid field needs prepare() before record()");
  bind_mesh(mesh);
  bind_targets(targets);
  bind_order(order);
  if (tetlets && (order || tetlets->max_cells != settings.tetlet_size))
    throw std::logic_error("IntervalShadingPass: tetlets draw in their own order, built for their own size");
  bind_tetlets(tetlets);
  const VkExtent2D e = targets.extent;
  const gpu::FrameUniforms frame = frame_uniforms(mesh, camera, e, settings, order != nullptr);
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
  intervals_recorded_ = true;
  intervals_by_compute_ = false;
}

void IntervalShadingPass::record_resolve(VkCommandBuffer cmd, VolumeTargets& targets, const ResolveSettings& settings,
                                         vk::GpuTimer& timer) {
  if (!std::exchange(intervals_recorded_, false))
    throw std::logic_error("IntervalShadingPass: the resolve reads what record_intervals() drew just before it");
  const bool emission = settings.quantity == Quantity::Color;
  const bool isosurface = settings.quantity == Quantity::Isosurface;
  const bool to_emission = emission || isosurface;
  const vk::Image& target = to_emission ? targets.emission : targets.optical_depth;
  const VkExtent2D e = targets.extent;
  bind_targets(targets);
  {
    vk::ScopedPass pass(timer, cmd, "resolve");
    // The resolve's descriptor set names both accumulation targets; the one this frame did not
    // draw is never read, but must be in the layout the set declares (its contents stay undefined).
    const vk::Image& other = to_emission ? targets.optical_depth : targets.emission;
    vk::image_barrier(cmd, other.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    if (intervals_by_compute_)
      vk::image_barrier(cmd, target.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    else
      vk::image_barrier(cmd, target.get(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    for (VkImage image : {targets.display.get(), targets.quantity.get()})
      vk::image_barrier(cmd, image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    gpu::ResolvePush push{};
    push.background = glm::vec4(settings.background, 1.0f);
    push.medium = glm::vec4(settings.medium, 1.0f);
    const uint32_t quantity = emission     ? PRISMOID_QUANTITY_COLOR
                              : isosurface ? PRISMOID_QUANTITY_ISOSURFACE
                              : settings.quantity == Quantity::Transmittance ? PRISMOID_QUANTITY_TRANSMITTANCE
                                                                             : PRISMOID_QUANTITY_OPTICAL_DEPTH;
    push.params = glm::uvec4(quantity, e.width, e.height, 0u);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, resolve_layout_.get(), 0, 1, &resolve_set_.set, 0, nullptr);
    vkCmdPushConstants(cmd, resolve_layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (e.width + 7) / 8, (e.height + 7) / 8, 1);
    for (VkImage image : {targets.display.get(), targets.quantity.get(), targets.emission.get()})
      vk::image_barrier(cmd, image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  }
}

}  // namespace prismoid::volume
