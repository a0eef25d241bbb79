#include "renderer/volume/volume_inputs.hpp"

#include <algorithm>
#include <chrono>
#include <glm/geometric.hpp>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/volume/float_limits.hpp"
#include "renderer/volume/interval_march.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "scene/tet_mesh.hpp"
#include "shaders/shared/volume.h"

namespace prismoid::volume {

void check_workgroup_settings(const ResolveSettings& settings) {
  if (std::find(kTetletSizes.begin(), kTetletSizes.end(), settings.tetlet_size) == kTetletSizes.end())
    throw InputError(setting("tetlet-size"), "must be 1, 4, 8 or 16 cells per mesh workgroup");
  if (settings.shared_vertices && settings.tetlet_size == 1)
    throw InputError(setting("shared-vertices"), "groups several cells per workgroup: use " + setting("tetlet-size", "4, 8 or 16"));
}

namespace {

constexpr VkFormat kOpticalDepthFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kQuantityFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kDisplayFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kEmissionFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

template <typename T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

glm::mat4 to_float(const glm::dmat4& m) { return glm::mat4(m); }

bool same_breakpoints(const std::vector<TfSample>& a, const std::vector<TfSample>& b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](const TfSample& x, const TfSample& y) {
           return x.x == y.x && x.rgb == y.rgb && x.sigma == y.sigma;
         });
}

double table_length(const GpuTetMesh& mesh) { return mesh.longest_edge > 0.0 ? mesh.longest_edge : 1.0; }

}  // namespace

void upload_fields(const vk::Device& device, GpuTetMesh& gpu, const TetMesh& mesh) {
  auto capped = [&](const std::vector<double>& v) {
    std::vector<float> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) out[i] = float(std::min(v[i], gpu.extinction_cap));
    if (out.empty()) out.push_back(0.0f);
    return out;
  };
  // Storage buffers cannot be empty: absent arrays get one unused value.
  auto floats = [](const std::vector<double>& v) {
    return v.empty() ? std::vector<float>{0.0f} : std::vector<float>(v.begin(), v.end());
  };
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu.cell_sigma = vk::upload_buffer(device, bytes_of(capped(mesh.cell_extinction)), usage);
  gpu.linear = mesh.linear_extinction();
  gpu.point_sigma = vk::upload_buffer(device, bytes_of(capped(mesh.point_extinction)), usage);
  gpu.scalar_per_point = !mesh.point_scalars.empty();
  gpu.has_scalars = gpu.scalar_per_point || !mesh.cell_scalars.empty();
  gpu.cell_scalar = vk::upload_buffer(device, bytes_of(floats(mesh.cell_scalars)), usage);
  gpu.point_scalar = vk::upload_buffer(device, bytes_of(floats(mesh.point_scalars)), usage);
  const auto& field = gpu.scalar_per_point ? mesh.point_scalars : mesh.cell_scalars;
  gpu.scalar_min = gpu.scalar_max = 0.0;
  if (!field.empty()) {
    const auto [lo, hi] = std::minmax_element(field.begin(), field.end());
    gpu.scalar_min = *lo;
    gpu.scalar_max = *hi;
  }
}

GpuTetMesh upload(const vk::Device& device, const TetMesh& mesh) {
  validate(mesh);
  GpuTetMesh gpu;
  const Bounds bounds = bounds_of(mesh);
  gpu.origin = bounds.center();
  gpu.extinction_cap = extinction_cap(glm::length(bounds.max - bounds.min));
  gpu.radius = 0.5 * glm::length(bounds.max - bounds.min);
  gpu.tet_count = static_cast<uint32_t>(mesh.tets.size());
  std::vector<glm::vec4> positions;
  positions.reserve(mesh.points.size());
  for (const auto& p : mesh.points) positions.emplace_back(glm::vec3(p - gpu.origin), 1.0f);
  std::vector<glm::uvec4> tets;
  tets.reserve(mesh.tets.size());
  for (const auto& t : mesh.tets) tets.emplace_back(t[0], t[1], t[2], t[3]);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu.positions = vk::upload_buffer(device, bytes_of(positions), usage);
  gpu.tets = vk::upload_buffer(device, bytes_of(tets), usage);
  upload_fields(device, gpu, mesh);
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

VolumeInputs::VolumeInputs(const vk::Device& device) : device_(device) {
  const glm::vec4 zero(0.0f);
  stub_ = vk::upload_buffer(device, std::as_bytes(std::span(&zero, 1)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

void VolumeInputs::prepare(const GpuTetMesh& mesh, const ResolveSettings& settings) {
  validate_march(mesh, settings);
  if (settings.march.enabled && settings.march.field.kind == FieldKind::Grid) upload_grid(settings.march.field.grid);
  // Where the rays end (opaque geometry), written while no frame is in flight.
  if (settings.depth_limit) {
    const std::vector<float>& limit = *settings.depth_limit;
    const VkDeviceSize bytes = std::max<VkDeviceSize>(limit.size() * sizeof(float), sizeof(float));
    if (depth_limit_.size() < bytes) depth_limit_ = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::HostVisible);
    depth_limit_.write(std::as_bytes(std::span(limit)));
  }
  if (settings.quantity != Quantity::Color) return;
  if (!mesh.has_scalars) throw InputError("color", "the dataset has no scalar field for the transfer function (choose one with " + setting("array", "NAME") + ")");
  validate(settings.transfer);
  if (settings.preintegration_size == 1 || settings.preintegration_size > 256)
    throw InputError(setting("preintegration-size"), "must be 0 (exact integration) or between 2 and 256 texels per axis");
}

void VolumeInputs::check_ready(const ResolveSettings& settings) const {
  if (settings.quantity == Quantity::Color &&
      (tf_buffer_.get() == VK_NULL_HANDLE || (settings.preintegration_size > 0 && table_buffer_.get() == VK_NULL_HANDLE)))
    throw std::logic_error("VolumeInputs: colour needs upload_transfer() before a frame");
  if (settings.march.enabled && settings.march.field.kind == FieldKind::Grid && settings.march.field.grid != grid_)
    throw std::logic_error("VolumeInputs: a grid field needs prepare() before a frame");
}

bool VolumeInputs::transfer_current(const GpuTetMesh& mesh, const ResolveSettings& settings) const {
  if (tf_buffer_.get() == VK_NULL_HANDLE || !same_breakpoints(breakpoints(settings.transfer), table_tf_)) return false;
  return settings.preintegration_size == 0 ||
         (table_buffer_.get() != VK_NULL_HANDLE && table_.size == settings.preintegration_size && table_.max_length == table_length(mesh));
}

double VolumeInputs::upload_transfer(const GpuTetMesh& mesh, const ResolveSettings& settings) {
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
  }
  if (!same_table) {
    table_ = build_preintegration_table(tf, settings.preintegration_size, max_length);
    table_buffer_ = vk::upload_buffer(device_, bytes_of(table_.texels), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  }
  table_tf_ = std::move(tf);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void VolumeInputs::upload_grid(const std::shared_ptr<const SampledGrid>& grid) {
  if (grid == grid_) return;
  const uint64_t bytes = uint64_t(grid->values.size()) * sizeof(float);
  if (bytes > device_.capabilities().max_storage_buffer_range)
    throw InputError(grid->name, "its " + std::to_string(grid->values.size()) + " samples exceed the " +
                                     std::to_string(device_.capabilities().max_storage_buffer_range) +
                                     " bytes one storage buffer may hold on " + device_.capabilities().name);
  device_.wait_idle();  // the old samples may still be read by a frame in flight
  grid_buffer_ = vk::upload_buffer(device_, bytes_of(grid->values), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  grid_ = grid;
}

gpu::FrameUniforms VolumeInputs::frame_uniforms(const GpuTetMesh& mesh, const Camera& camera, VkExtent2D e,
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

}  // namespace prismoid::volume
