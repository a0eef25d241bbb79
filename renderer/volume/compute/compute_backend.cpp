#include "renderer/volume/compute/compute_backend.hpp"
#include "scene/setting_names.hpp"

#include <string>
#include <vector>

namespace prismoid::volume {

namespace {

std::unique_ptr<GpuVolumeBackend> make(const BackendScene& scene) { return std::make_unique<ComputeBackend>(scene); }

// Its passes: the cells binned into tiles and sorted there on the GPU, then each pixel's
// intervals found on its own ray.
void plan_intervals(const frame::VolumeContents& volume, const frame::FrameSettings& settings, std::vector<frame::PlannedPass>& run,
                    std::vector<frame::SkippedPass>& skipped) {
  skipped.push_back({interval_pass_name(settings.resolve), "compute backend: tiles rasterized in compute (bin-cells, tile-sort, tile-raster)"});
  std::string bin_why = "compute backend: each cell's conservative screen bounds in 8x8 tiles and its depth key; pair counts "
                        "prefix-summed into places; (tile, depth key) pairs written";
  if (!settings.backend_reason.empty()) bin_why += "; " + settings.backend_reason;
  run.push_back({frame::PassId::BinCells, "bin-cells", frame::PassKind::Gpu, bin_why});
  run.push_back({frame::PassId::TileSort, "tile-sort", frame::PassKind::Gpu,
                 "the pairs sorted by tile, then depth, with the GPU radix sort, counted on the GPU (no read back); each tile's range"});
  std::string why = frame::interval_reason(volume, settings);
  why = why.substr(0, why.rfind("; "));  // the workgroup size is the mesh shader's
  why += "; one workgroup per tile, each pixel's exact interval per cell on its own ray, clipped at the near plane";
  if (volume.optics == frame::VolumeOptics::EmissionAbsorption) why += "; composited in each pixel's own depth order (k-buffer)";
  run.push_back({frame::PassId::TileRaster, "tile-raster", frame::PassKind::Gpu, why});
}

}  // namespace

const VolumeBackendInfo& compute_backend() {
  static const VolumeBackendInfo info{
      .name = "compute",
      .summary = "compute shaders on every core: cells binned into tiles, each pixel's exact intervals on its own ray, composited "
                 "in its own depth order",
      .needs = {},
      .supports = {.march = true, .depth_limit = true},
      .passes = {.backend = "compute",
                 .chosen_order = false,
                 .own_order = "compute backend: each pixel composites its own intervals in their depth order",
                 .isosurface_order = "an isosurface is order-independent (each pixel keeps its nearest hit)",
                 .tetlets = false,
                 .no_tetlets = "compute backend: cells are loaded per tile",
                 .tetlets_refused = "groups cells into mesh-shader workgroups: the compute backend loads each cell's points per tile; "
                                    "use it with the mesh backend",
                 .intervals = plan_intervals},
      .make = make,
  };
  return info;
}

ComputeBackend::ComputeBackend(const BackendScene& scene) : mesh_(scene.mesh), intervals_(scene.device) {}

void ComputeBackend::check(const BackendPrepare& frame) {
  // The last frame (finished: no frame is in flight here) may have asked for more pairs than
  // the buffers held and drawn only those that fit; this one gets room for them all.
  if (intervals_.recorded()) intervals_.reserve_pairs(intervals_.read_stats().pairs);
  intervals_.prepare(mesh_, frame.settings.resolve, frame.extent);
}

BackendHistory ComputeBackend::history(const frame::FrameSettings& settings) const {
  (void)settings;
  return {};  // each frame bins and sorts again; it builds no tetlets
}

bool ComputeBackend::run_cpu(const frame::PlannedPass& pass, const BackendPrepare& frame) {
  (void)pass;
  (void)frame;
  return false;  // no CPU pass of its own
}

void ComputeBackend::prepared(const BackendPrepare& frame, const frame::FramePlan& plan, frame::FrameReport& report) {
  (void)plan;
  report.backend_bytes = intervals_.bytes();
  if (order_dependent(frame.settings.resolve.quantity)) {
    // Exact unless a pixel's intervals arrive too far out of order for its k-buffer, which the
    // frame counts (FrameReport::inexact_pixels, once it finished).
    report.ordering = "per-pixel (k-buffer of " + std::to_string(ComputeIntervals::kKBuffer) + " over tiles sorted by depth)";
    report.order_exact = false;
  } else {
    // Additive quantities: any order gives the same sum, so nothing sorts.
    report.ordering = "none (order-independent)";
    report.order_exact = true;
  }
}

bool ComputeBackend::record(const frame::PlannedPass& pass, const BackendRecord& frame) {
  switch (pass.id) {
    case frame::PassId::BinCells:
      intervals_.record_bin(frame.cmd, mesh_, frame.inputs, frame.targets, frame.camera, frame.settings.resolve, frame.timer);
      return true;
    case frame::PassId::TileSort:
      intervals_.record_sort(frame.cmd, frame.timer);
      return true;
    case frame::PassId::TileRaster:
      intervals_.record_raster(frame.cmd, frame.targets, frame.timer);
      return true;
    default:
      return false;
  }
}

void ComputeBackend::recorded(const frame::FrameSettings& settings) { (void)settings; }

bool ComputeBackend::finished(const frame::FrameSettings& settings, frame::FrameReport& report) {
  // A frame that needed more (tile, cell) pairs than the buffers held drew only part of its
  // cells: it is drawn again with room for all of them (check() grows the buffers).
  const ComputeIntervalStats stats = intervals_.read_stats();
  report.counts_known = true;
  report.pairs = stats.sorted;
  report.inexact_pixels = stats.inexact_pixels;
  report.big_cells = stats.big_cells;
  report.split_tiles = stats.split_tiles;
  report.chunks = stats.chunks;
  report.redone_tiles = stats.redone_tiles;
  if (order_dependent(settings.resolve.quantity)) report.order_exact = stats.inexact_pixels == 0;
  return stats.complete();
}

}  // namespace prismoid::volume
