#include "renderer/volume/mesh/mesh_backend.hpp"

#include <algorithm>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/vk/timer.hpp"
#include "renderer/volume/visibility_order.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {

namespace {

std::unique_ptr<GpuVolumeBackend> make(const BackendScene& scene) { return std::make_unique<MeshBackend>(scene); }

// One pass: a mesh-shader workgroup per cell (or tetlet), the fragments integrating the intervals.
void plan_intervals(const frame::VolumeContents& volume, const frame::FrameSettings& settings, std::vector<frame::PlannedPass>& run,
                    std::vector<frame::SkippedPass>& skipped) {
  (void)skipped;
  std::string why = frame::interval_reason(volume, settings);
  if (!settings.backend_reason.empty()) why += "; " + settings.backend_reason;
  run.push_back({frame::PassId::Intervals, interval_pass_name(settings.resolve), frame::PassKind::Gpu, why});
}

}  // namespace

const VolumeBackendInfo& mesh_backend() {
  static const VolumeBackendInfo info{
      .name = "mesh",
      .summary = "mesh shaders and the rasterizer (interval shading, Tricard 2024): each cell's proxy drawn, each fragment its "
                 "interval",
      .needs = {vk::Feature::MeshShader},
      .supports = {.march = true, .depth_limit = true},
      .passes = {.backend = "mesh", .chosen_order = true, .tetlets = true, .intervals = plan_intervals},
      .make = make,
  };
  return info;
}

// The CPU-made orders and groupings, each made on first use.
struct MeshBackend::Orders {
  const TetMesh& geometry;
  std::optional<TetAdjacency> adjacency;  // built once
  vk::Buffer exact_host;                  // host-visible, written by the exact-order pass
  vk::Buffer exact;                       // device-local copy the mesh shader reads
  std::string exact_description;          // the last exact order's report, kept for frames reusing it
  bool exact_exact = false;
  std::map<uint32_t, GpuTetlets> tetlets;  // by cells per workgroup
};

MeshBackend::MeshBackend(const BackendScene& scene)
    : device_(scene.device), mesh_(scene.mesh), interval_(scene.device), orders_(std::make_unique<Orders>(Orders{scene.geometry})) {}

MeshBackend::~MeshBackend() = default;

void MeshBackend::check(const BackendPrepare& frame) { interval_.prepare(frame.settings.resolve); }

BackendHistory MeshBackend::history(const frame::FrameSettings& settings) const {
  return {recorded_order_, orders_->tetlets.count(settings.resolve.tetlet_size) > 0};
}

bool MeshBackend::run_cpu(const frame::PlannedPass& pass, const BackendPrepare& frame) {
  Orders& o = *orders_;
  switch (pass.id) {
    case frame::PassId::BuildTetlets:
      o.tetlets.emplace(frame.settings.resolve.tetlet_size, upload_tetlets(device_, o.geometry, frame.settings.resolve.tetlet_size));
      return true;
    case frame::PassId::ExactOrder: {
      if (!o.adjacency) o.adjacency = build_adjacency(o.geometry);
      const VisibilityOrder order = exact_order(o.geometry, *o.adjacency, frame.camera.eye);
      const VkDeviceSize bytes = std::max<VkDeviceSize>(order.front_to_back.size() * sizeof(uint32_t), 4);
      if (o.exact_host.size() < bytes) {
        // Read by every mesh workgroup: keep it in device memory, not across the bus.
        o.exact_host = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::HostVisible);
        o.exact = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             vk::MemoryUse::DeviceLocal);
      }
      o.exact_host.write(std::as_bytes(std::span(order.front_to_back)));
      o.exact_exact = order.exact;
      o.exact_description = "exact (topological over face adjacency)";
      if (!order.acyclic)
        o.exact_description += "; " + std::to_string(order.cells_in_cycles) + " cells in visibility cycles placed by distance";
      if (!o.adjacency->convex_boundary) o.exact_description += "; non-convex boundary: approximate across gaps";
      return true;
    }
    default:
      return false;
  }
}

void MeshBackend::prepared(const BackendPrepare& frame, const frame::FramePlan& plan, frame::FrameReport& report) {
  const frame::FrameSettings& settings = frame.settings;
  Orders& o = *orders_;
  order_ = nullptr;
  draw_tetlets_ = nullptr;
  if (settings.resolve.shared_vertices) {
    draw_tetlets_ = &o.tetlets.at(settings.resolve.tetlet_size);
    report.tetlet_points_per_cell = draw_tetlets_->points_per_cell;
  }
  const bool ordered = plan.find(frame::PassId::Sort) || plan.find(frame::PassId::UploadOrder) || plan.reuses_order;
  const std::string reused = plan.reuses_order ? "; reused: camera still" : "";
  if (!order_dependent(settings.resolve.quantity)) {
    // Additive quantities: any order gives the same sum, so nothing sorts.
    report.ordering = "none (order-independent)";
    report.order_exact = true;
  } else if (!ordered) {
    report.ordering = "mesh-order (unsorted)";
  } else if (settings.ordering == frame::Ordering::GpuSort) {
    if (!gpu_sort_) gpu_sort_ = std::make_unique<VisibilitySort>(device_);
    order_ = &gpu_sort_->order();
    report.ordering = "gpu-sort (centroid distance)" + reused;
  } else {
    order_ = &o.exact;
    report.order_exact = o.exact_exact;
    report.ordering = o.exact_description + reused;
  }
}

bool MeshBackend::record(const frame::PlannedPass& pass, const BackendRecord& frame) {
  Orders& o = *orders_;
  switch (pass.id) {
    case frame::PassId::Sort:
      gpu_sort_->record(frame.cmd, mesh_.positions, mesh_.tets, mesh_.tet_count, glm::vec3(frame.camera.eye - mesh_.origin), frame.timer);
      return true;
    case frame::PassId::UploadOrder: {
      vk::ScopedPass scoped(frame.timer, frame.cmd, pass.name);
      // The previous frame's mesh shader read the buffer; this frame's reads wait for the copy.
      vk::buffer_barrier(frame.cmd, {o.exact.get()}, VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                         VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
      const VkBufferCopy region{0, 0, std::min(o.exact_host.size(), o.exact.size())};
      vkCmdCopyBuffer(frame.cmd, o.exact_host.get(), o.exact.get(), 1, &region);
      vk::buffer_barrier(frame.cmd, {o.exact.get()}, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
      return true;
    }
    case frame::PassId::Intervals:
      interval_.record(frame.cmd, mesh_, frame.inputs, frame.targets, frame.camera, frame.settings.resolve, frame.timer, order_,
                       draw_tetlets_);
      return true;
    default:
      return false;
  }
}

void MeshBackend::recorded(const frame::FrameSettings& settings) {
  recorded_order_ = order_ ? std::optional<frame::Ordering>(settings.ordering) : std::nullopt;
}

bool MeshBackend::finished(const frame::FrameSettings& settings, frame::FrameReport& report) {
  (void)settings;
  if (const auto counts = draw_counts()) {  // the statistics count the mesh-shader draw
    report.counted = true;
    report.primitives = counts->primitives;
    report.fragments = counts->fragments;
  }
  return true;
}

std::optional<DrawCounts> MeshBackend::draw_counts() const {
  if (!interval_.counts_draws()) return std::nullopt;
  const auto counts = interval_.read_counts();
  return DrawCounts{counts.primitives, counts.fragments};
}

}  // namespace prismoid::volume
