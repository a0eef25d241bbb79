#include "renderer/frame/frame_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <string>

#include "renderer/vk/device.hpp"
#include "scene/input_error.hpp"
#include "renderer/volume/visibility_order.hpp"
#include "renderer/volume/visibility_sort.hpp"

namespace prismoid::frame {

const char* ordering_name(Ordering ordering) {
  switch (ordering) {
    case Ordering::MeshOrder: return "mesh-order";
    case Ordering::GpuSort: return "gpu-sort";
    case Ordering::Exact: return "exact";
  }
  return "?";
}

// The visibility orderings a frame may use, each made on first use.
struct FrameRenderer::Orderings {
  TetMesh geometry;                                  // points and cells, for the exact order
  std::optional<volume::TetAdjacency> adjacency;     // built once
  vk::Buffer exact_order_host;                       // host-visible, written by prepare()
  vk::Buffer exact_order;                            // device-local copy the mesh shader reads
  bool upload_exact_order = false;                   // record() copies host -> device first
  std::unique_ptr<volume::VisibilitySort> gpu_sort;  // records its pass in record()
  const vk::Buffer* order = nullptr;                 // what the next record() draws with (nullptr: mesh order)
  std::map<uint32_t, volume::GpuTetlets> tetlets;    // by cells per workgroup, built on first use
  const volume::GpuTetlets* draw_tetlets = nullptr;  // what the next record() draws (nullptr: cells)
  bool sort_on_gpu = false;                          // record() sorts before drawing
};

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& mesh)
    : device_(device), mesh_(volume::upload(device, mesh)), bounds_(bounds_of(mesh)), interval_(device),
      orderings_(std::make_unique<Orderings>()), offscreen_timer_(device, 16) {
  orderings_->geometry.name = mesh.name;
  orderings_->geometry.points = mesh.points;
  orderings_->geometry.tets = mesh.tets;
}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::resize(VkExtent2D extent) {
  if (extent.width == targets_.extent.width && extent.height == targets_.extent.height) return;
  device_.wait_idle();
  targets_ = volume::create_targets(device_, extent);
}

FrameReport FrameRenderer::prepare(const Camera& camera, const FrameSettings& settings) {
  FrameReport report;
  for (const vk::Buffer* b : {&mesh_.positions, &mesh_.tets, &mesh_.cell_sigma, &mesh_.point_sigma, &mesh_.cell_scalar, &mesh_.point_scalar})
    report.mesh_bytes += b->size();
  const double table_ms = interval_.prepare(mesh_, settings.resolve);
  if (table_ms > 0.0)
    report.cpu_passes.push_back({settings.resolve.preintegration_size > 0 ? "preintegrate" : "transfer-function upload", table_ms});
  Orderings& o = *orderings_;
  o.order = nullptr;
  o.sort_on_gpu = false;
  o.upload_exact_order = false;
  o.draw_tetlets = nullptr;
  if (settings.resolve.shared_vertices) {
    if (volume::order_dependent(settings.resolve.quantity) && settings.ordering != Ordering::MeshOrder)
      throw InputError("--shared-vertices", "tetlets fix the order cells are drawn in: use it with optical depth or "
                                            "transmittance, or with --mode interval");
    auto found = o.tetlets.find(settings.resolve.tetlet_size);
    if (found == o.tetlets.end()) {
      const auto start = std::chrono::steady_clock::now();
      found = o.tetlets.emplace(settings.resolve.tetlet_size, volume::upload_tetlets(device_, o.geometry, settings.resolve.tetlet_size)).first;
      report.cpu_passes.push_back(
          {"build-tetlets", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
    }
    o.draw_tetlets = &found->second;
    report.tetlet_points_per_cell = found->second.points_per_cell;
  }
  if (!volume::order_dependent(settings.resolve.quantity)) {
    // Additive quantities: any order gives the same sum, so nothing sorts.
    report.ordering = "none (order-independent)";
    report.order_exact = true;
    return report;
  }
  switch (settings.ordering) {
    case Ordering::MeshOrder:
      report.ordering = "mesh-order (unsorted)";
      return report;
    case Ordering::GpuSort:
      if (!o.gpu_sort) o.gpu_sort = std::make_unique<volume::VisibilitySort>(device_);
      o.sort_on_gpu = mesh_.tet_count > 0;
      o.order = mesh_.tet_count > 0 ? &o.gpu_sort->order() : nullptr;
      report.ordering = "gpu-sort (centroid distance)";
      return report;
    case Ordering::Exact: {
      const auto start = std::chrono::steady_clock::now();
      if (!o.adjacency) o.adjacency = volume::build_adjacency(o.geometry);
      const volume::VisibilityOrder order = volume::exact_order(o.geometry, *o.adjacency, camera.eye);
      const VkDeviceSize bytes = std::max<VkDeviceSize>(order.front_to_back.size() * sizeof(uint32_t), 4);
      if (o.exact_order_host.size() < bytes) {
        // Read by every mesh workgroup: keep it in device memory, not across the bus.
        o.exact_order_host = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::HostVisible);
        o.exact_order = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                   vk::MemoryUse::DeviceLocal);
      }
      o.exact_order_host.write(std::as_bytes(std::span(order.front_to_back)));
      o.upload_exact_order = mesh_.tet_count > 0;
      o.order = mesh_.tet_count > 0 ? &o.exact_order : nullptr;
      report.order_exact = order.exact;
      report.ordering = "exact (topological over face adjacency)";
      if (!order.acyclic)
        report.ordering += "; " + std::to_string(order.cells_in_cycles) + " cells in visibility cycles placed by distance";
      if (!o.adjacency->convex_boundary) report.ordering += "; non-convex boundary: approximate across gaps";
      report.cpu_passes.push_back(
          {"exact-order", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count()});
      return report;
    }
  }
  return report;
}

void FrameRenderer::record(VkCommandBuffer cmd, const Camera& camera, const FrameSettings& settings, vk::GpuTimer& timer) {
  Orderings& o = *orderings_;
  if (o.sort_on_gpu)
    o.gpu_sort->record(cmd, mesh_.positions, mesh_.tets, mesh_.tet_count, glm::vec3(camera.eye - mesh_.origin), timer);
  if (o.upload_exact_order) {
    vk::ScopedPass pass(timer, cmd, "upload-order");
    // The previous frame's mesh shader read the buffer; this frame's reads wait for the copy.
    vk::buffer_barrier(cmd, {o.exact_order.get()}, VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                       VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkBufferCopy region{0, 0, std::min(o.exact_order_host.size(), o.exact_order.size())};
    vkCmdCopyBuffer(cmd, o.exact_order_host.get(), o.exact_order.get(), 1, &region);
    vk::buffer_barrier(cmd, {o.exact_order.get()}, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
  }
  interval_.record(cmd, mesh_, targets_, camera, settings.resolve, timer, o.order, o.draw_tetlets);
}

OffscreenFrame FrameRenderer::render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent) {
  resize(extent);
  OffscreenFrame frame;
  frame.report = prepare(camera, settings);
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    offscreen_timer_.reset(cmd);
    record(cmd, camera, settings, offscreen_timer_);
  });
  frame.width = extent.width;
  frame.height = extent.height;
  const size_t pixels = size_t(extent.width) * extent.height;
  frame.quantity.resize(pixels);
  frame.display.resize(pixels * 4);
  vk::read_image(device_, targets_.quantity, sizeof(float), std::as_writable_bytes(std::span(frame.quantity)));
  vk::read_image(device_, targets_.display, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.display)));
  if (settings.resolve.quantity == volume::Quantity::Color || settings.resolve.quantity == volume::Quantity::Isosurface) {
    frame.emission.resize(pixels * 4);
    vk::read_image(device_, targets_.emission, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.emission)));
  }
  frame.passes = offscreen_timer_.read();
  if (interval_.counts_draws()) {
    const auto counts = interval_.read_counts();
    frame.report.counted = true;
    frame.report.primitives = counts.primitives;
    frame.report.fragments = counts.fragments;
  }
  return frame;
}

}  // namespace prismoid::frame
