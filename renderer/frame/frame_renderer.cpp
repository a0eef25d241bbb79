#include "renderer/frame/frame_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/volume/compute_intervals.hpp"
#include "scene/input_error.hpp"
#include "renderer/volume/visibility_order.hpp"
#include "renderer/volume/visibility_sort.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// The visibility orderings a frame may use, each made on first use.
struct FrameRenderer::Orderings {
  TetMesh geometry;                                  // points and cells, for the exact order
  bool point_extinction = false, point_scalars = false;  // what the mesh's fields are (for the planner)
  std::optional<volume::TetAdjacency> adjacency;     // built once
  vk::Buffer exact_order_host;                       // host-visible, written by the exact-order pass
  vk::Buffer exact_order;                            // device-local copy the mesh shader reads
  std::string exact_description;                     // the last exact order's report, kept for frames reusing it
  bool exact_exact = false;
  std::unique_ptr<volume::VisibilitySort> gpu_sort;  // records its pass in record()
  const vk::Buffer* order = nullptr;                 // what the next record() draws with (nullptr: mesh order)
  std::map<uint32_t, volume::GpuTetlets> tetlets;    // by cells per workgroup, built on first use
  const volume::GpuTetlets* draw_tetlets = nullptr;  // what the next record() draws (nullptr: cells)
};

// What the last recorded frame left in device memory, for the planner's reuse decisions.
struct FrameRenderer::Recorded {
  bool any = false;
  glm::dvec3 eye{0.0};
  std::optional<Ordering> order;  // the ordering that made the order buffer that frame drew with
};

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& mesh)
    : FrameRenderer(device, mesh, frame_units(bounds_of(mesh))) {}

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& world, const FrameUnits& units)
    : FrameRenderer(device, world, units, in_units(world, units)) {}

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& world, const FrameUnits& units, const TetMesh& local)
    : device_(device), units_(units), mesh_(volume::upload(device, local)), bounds_(bounds_of(world)),
      float_facts_(volume::float_facts(local)), inputs_(device), interval_(device), resolve_(device),
      orderings_(std::make_unique<Orderings>()), recorded_(std::make_unique<Recorded>()), offscreen_timer_(device, 16) {
  float_facts_.unit = units_.unit;
  orderings_->geometry.name = local.name;
  orderings_->geometry.points = local.points;
  orderings_->geometry.tets = local.tets;
  orderings_->point_extinction = local.linear_extinction();
  orderings_->point_scalars = !local.point_scalars.empty();
}

FrameSettings FrameRenderer::local_settings(const FrameSettings& settings) const {
  FrameSettings local = settings;
  if (settings.resolve.depth_limit && settings.resolve.depth_limit != limit_world_) {
    limit_local_ = limit_in_units(*settings.resolve.depth_limit, units_);
    limit_world_ = settings.resolve.depth_limit;  // kept, so its address names this limit
  }
  local.resolve = in_units(settings.resolve, units_, limit_local_);
  return local;
}

FrameRenderer::~FrameRenderer() = default;

const volume::VisibilitySort* FrameRenderer::gpu_sort() const { return orderings_->gpu_sort.get(); }

void FrameRenderer::forget_history() { *recorded_ = Recorded{}; }

void FrameRenderer::resize(VkExtent2D extent) {
  if (extent.width == targets_.extent.width && extent.height == targets_.extent.height) return;
  device_.wait_idle();
  targets_ = volume::create_targets(device_, extent);
}

SceneContents FrameRenderer::scene_contents(const Camera& camera, const FrameSettings& world_settings) const {
  const FrameSettings settings = local_settings(world_settings);
  const Orderings& o = *orderings_;
  SceneContents scene;
  scene.volumes.push_back(volume_contents(mesh_.tet_count, o.point_extinction, o.point_scalars, settings.resolve));
  const Recorded& last = *recorded_;
  scene.camera_moved = !last.any || camera.eye != last.eye;
  scene.scene_moved = !last.any;  // the mesh and its fields are fixed for the renderer's life
  scene.transfer_changed =
      settings.resolve.quantity == volume::Quantity::Color && !inputs_.transfer_current(mesh_, settings.resolve);
  scene.order_kept = last.order;
  scene.tetlets_built = o.tetlets.count(settings.resolve.tetlet_size) > 0;
  return scene;
}

FrameReport FrameRenderer::prepare(const Camera& world_camera, const FrameSettings& world_settings) {
  plan_.reset();
  const Camera camera = in_units(world_camera, units_);
  const FrameSettings settings = local_settings(world_settings);
  FrameReport report;
  for (const vk::Buffer* b : {&mesh_.positions, &mesh_.tets, &mesh_.cell_sigma, &mesh_.point_sigma, &mesh_.cell_scalar, &mesh_.point_scalar})
    report.mesh_bytes += b->size();
  const bool compute = settings.backend == IntervalBackend::Compute;
  // Rays ending at opaque geometry: both backends clip each interval at the pixel's limit (the
  // tile raster, the fragment stages), for the quantities the CPU reference integrates.
  if (const auto& limit = settings.resolve.depth_limit) {
    if (limit->size() != size_t(targets_.extent.width) * targets_.extent.height)
      throw InputError("depth limit", "has " + std::to_string(limit->size()) + " values for a " + std::to_string(targets_.extent.width) +
                                          "x" + std::to_string(targets_.extent.height) + " frame");
    if (settings.resolve.march.enabled || settings.resolve.quantity == volume::Quantity::Isosurface)
      throw InputError("depth limit", "is not followed when marching a field or drawing an isosurface");
  }
  // Checks the settings before anything is planned; the compute backend needs no mesh pipeline.
  interval_.prepare(settings.resolve, !compute);
  inputs_.prepare(mesh_, settings.resolve);
  report.warnings =
      volume::check_float_limits(float_facts_, camera, targets_.extent.width, targets_.extent.height, settings.resolve, true,
                                 &orderings_->geometry.points)
          .warnings;
  report.plan = plan_frame(scene_contents(world_camera, world_settings), settings);
  report.backend = interval_backend_name(settings.backend);
  if (compute) {
    if (!compute_) compute_ = std::make_unique<volume::ComputeIntervals>(device_);
    // The last frame (finished: no frame is in flight here) may have asked for more pairs
    // than the buffers held and drawn only those that fit; this one gets room for them all.
    if (compute_->recorded()) compute_->reserve_pairs(compute_->read_stats().pairs);
    compute_->prepare(mesh_, settings.resolve, targets_.extent);
    report.backend_bytes = compute_->bytes();
  }
  Orderings& o = *orderings_;
  o.order = nullptr;
  o.draw_tetlets = nullptr;
  for (const PlannedPass& pass : report.plan.passes) {
    if (pass.kind != PassKind::Cpu) continue;
    const auto start = std::chrono::steady_clock::now();
    switch (pass.id) {
      case PassId::TransferUpload:
      case PassId::Preintegrate:
        inputs_.upload_transfer(mesh_, settings.resolve);
        break;
      case PassId::BuildTetlets:
        o.tetlets.emplace(settings.resolve.tetlet_size, volume::upload_tetlets(device_, o.geometry, settings.resolve.tetlet_size));
        break;
      case PassId::ExactOrder: {
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
        o.exact_exact = order.exact;
        o.exact_description = "exact (topological over face adjacency)";
        if (!order.acyclic)
          o.exact_description += "; " + std::to_string(order.cells_in_cycles) + " cells in visibility cycles placed by distance";
        if (!o.adjacency->convex_boundary) o.exact_description += "; non-convex boundary: approximate across gaps";
        break;
      }
      default:
        throw std::logic_error("FrameRenderer: the plan has a CPU pass it cannot run: " + pass.name);
    }
    report.cpu_passes.push_back({pass.name, ms_since(start)});
  }
  if (settings.resolve.shared_vertices) {
    o.draw_tetlets = &o.tetlets.at(settings.resolve.tetlet_size);
    report.tetlet_points_per_cell = o.draw_tetlets->points_per_cell;
  }
  const bool ordered = report.plan.find(PassId::Sort) || report.plan.find(PassId::UploadOrder) || report.plan.reuses_order;
  const std::string reused = report.plan.reuses_order ? "; reused: camera still" : "";
  if (compute && volume::order_dependent(settings.resolve.quantity)) {
    // Exact unless a pixel's intervals arrive too far out of order for its k-buffer, which the
    // frame counts (FrameReport::inexact_pixels, once it finished).
    report.ordering = "per-pixel (k-buffer of " + std::to_string(volume::ComputeIntervals::kKBuffer) + " over tiles sorted by depth)";
    report.order_exact = false;
  } else if (!volume::order_dependent(settings.resolve.quantity)) {
    // Additive quantities: any order gives the same sum, so nothing sorts.
    report.ordering = "none (order-independent)";
    report.order_exact = true;
  } else if (!ordered) {
    report.ordering = "mesh-order (unsorted)";
  } else if (settings.ordering == Ordering::GpuSort) {
    if (!o.gpu_sort) o.gpu_sort = std::make_unique<volume::VisibilitySort>(device_);
    o.order = &o.gpu_sort->order();
    report.ordering = "gpu-sort (centroid distance)" + reused;
  } else {
    o.order = &o.exact_order;
    report.order_exact = o.exact_exact;
    report.ordering = o.exact_description + reused;
  }
  plan_ = report.plan;
  plan_eye_ = world_camera.eye;
  return report;
}

void FrameRenderer::record(VkCommandBuffer cmd, const Camera& world_camera, const FrameSettings& world_settings,
                           vk::GpuTimer& timer) {
  if (!plan_) throw std::logic_error("FrameRenderer: record() needs prepare() first");
  if (world_camera.eye != plan_eye_) throw std::logic_error("FrameRenderer: record() for another eye than prepare() planned for");
  const Camera camera = in_units(world_camera, units_);
  const FrameSettings settings = local_settings(world_settings);
  Orderings& o = *orderings_;
  const size_t first_timed = timer.recorded().size();
  for (const PlannedPass& pass : plan_->passes) {
    if (pass.kind != PassKind::Gpu) continue;
    switch (pass.id) {
      case PassId::Sort:
        o.gpu_sort->record(cmd, mesh_.positions, mesh_.tets, mesh_.tet_count, glm::vec3(camera.eye - mesh_.origin), timer);
        break;
      case PassId::UploadOrder: {
        vk::ScopedPass scoped(timer, cmd, pass.name);
        // The previous frame's mesh shader read the buffer; this frame's reads wait for the copy.
        vk::buffer_barrier(cmd, {o.exact_order.get()}, VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                           VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
        const VkBufferCopy region{0, 0, std::min(o.exact_order_host.size(), o.exact_order.size())};
        vkCmdCopyBuffer(cmd, o.exact_order_host.get(), o.exact_order.get(), 1, &region);
        vk::buffer_barrier(cmd, {o.exact_order.get()}, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
        break;
      }
      case PassId::Intervals:
        interval_.record(cmd, mesh_, inputs_, targets_, camera, settings.resolve, timer, o.order, o.draw_tetlets);
        break;
      case PassId::BinCells:
        compute_->record_bin(cmd, mesh_, inputs_, targets_, camera, settings.resolve, timer);
        break;
      case PassId::TileSort:
        compute_->record_sort(cmd, timer);
        break;
      case PassId::TileRaster:
        compute_->record_raster(cmd, targets_, timer);
        break;
      case PassId::Resolve:
        resolve_.record(cmd, targets_, settings.resolve,
                        settings.backend == IntervalBackend::Compute ? volume::AccumulatedBy::Compute : volume::AccumulatedBy::Raster,
                        timer);
        break;
      default:
        throw std::logic_error("FrameRenderer: the plan has a GPU pass it cannot record: " + pass.name);
    }
  }
  // The plan is the single source of truth: what was timed is exactly what was planned.
  const std::vector<std::string> timed(timer.recorded().begin() + std::ptrdiff_t(first_timed), timer.recorded().end());
  if (timed != plan_->gpu_pass_names()) throw std::logic_error("FrameRenderer: recorded passes differ from the plan");
  recorded_->any = true;
  recorded_->eye = world_camera.eye;
  recorded_->order = o.order ? std::optional<Ordering>(settings.ordering) : std::nullopt;
}

OffscreenFrame FrameRenderer::render_timed(const Camera& camera, const FrameSettings& settings, VkExtent2D extent) {
  resize(extent);
  OffscreenFrame frame;
  const bool compute = settings.backend == IntervalBackend::Compute;
  for (int attempt = 0;; ++attempt) {
    frame.report = prepare(camera, settings);
    device_.submit_and_wait([&](VkCommandBuffer cmd) {
      offscreen_timer_.reset(cmd);
      record(cmd, camera, settings, offscreen_timer_);
    });
    if (!compute) break;
    // A frame that needed more (tile, cell) pairs than the buffers held drew only part of its
    // cells: it is drawn again with room for all of them (prepare() grows the buffers).
    const volume::ComputeIntervalStats stats = compute_->read_stats();
    frame.report.counts_known = true;
    frame.report.pairs = stats.sorted;
    frame.report.inexact_pixels = stats.inexact_pixels;
    frame.report.big_cells = stats.big_cells;
    frame.report.split_tiles = stats.split_tiles;
    frame.report.chunks = stats.chunks;
    frame.report.redone_tiles = stats.redone_tiles;
    if (volume::order_dependent(settings.resolve.quantity)) frame.report.order_exact = stats.inexact_pixels == 0;
    if (stats.complete()) break;
    if (attempt > 0) throw std::logic_error("FrameRenderer: the compute backend's pairs did not fit after growing");
    forget_history();
  }
  frame.width = extent.width;
  frame.height = extent.height;
  frame.passes = offscreen_timer_.read();
  if (interval_.counts_draws() && settings.backend == IntervalBackend::Mesh) {  // the statistics count the mesh-shader draw
    const auto counts = interval_.read_counts();
    frame.report.counted = true;
    frame.report.primitives = counts.primitives;
    frame.report.fragments = counts.fragments;
  }
  return frame;
}

OffscreenFrame FrameRenderer::render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent) {
  OffscreenFrame frame = render_timed(camera, settings, extent);
  const size_t pixels = size_t(extent.width) * extent.height;
  frame.quantity.resize(pixels);
  frame.display.resize(pixels * 4);
  vk::read_image(device_, targets_.quantity, sizeof(float), std::as_writable_bytes(std::span(frame.quantity)));
  vk::read_image(device_, targets_.display, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.display)));
  if (settings.resolve.quantity == volume::Quantity::Color || settings.resolve.quantity == volume::Quantity::Isosurface) {
    frame.emission.resize(pixels * 4);
    vk::read_image(device_, targets_.emission, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.emission)));
    // An isosurface's hit distance is a length: back to world units.
    if (settings.resolve.quantity == volume::Quantity::Isosurface)
      for (size_t i = 3; i < frame.emission.size(); i += 4) frame.emission[i] = float(double(frame.emission[i]) * units_.unit);
  }
  return frame;
}

}  // namespace prismoid::frame
