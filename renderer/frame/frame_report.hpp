#pragma once
// What a volume frame did and the images it made, whichever backend drew it (the GPU ones
// through FrameRenderer, the CPU reference directly): plain data every volume backend fills.
#include <cstdint>
#include <string>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/vk/timer.hpp"

namespace prismoid::frame {

// What ran, besides the GPU passes: the ordering actually used and CPU work done.
struct FrameReport {
  FramePlan plan;                        // the passes this frame runs, why, and those it leaves out
  std::string ordering = "none";        // "none (order-independent)", "gpu-sort", "exact", ...
  bool order_exact = false;              // whether the order was exact for every ray
  std::vector<vk::PassTiming> cpu_passes;  // CPU stages (milliseconds of wall time)
  uint64_t mesh_bytes = 0;               // the mesh's GPU buffers (positions, cells, fields)
  double tetlet_points_per_cell = 0.0;   // with shared vertices: points loaded per cell drawn (4 without)
  // What the interval pass drew (offscreen frames, on devices with pipeline statistics).
  bool counted = false;
  uint64_t primitives = 0;  // proxy triangles that reached the rasterizer's clipper
  uint64_t fragments = 0;   // fragment-shader invocations: (pixel, segment) pairs shaded
  // What float32 renders only approximately in this frame, and by how much
  // (volume::check_float_limits); empty when the frame is exact to its tolerances.
  std::vector<std::string> warnings;
  // The interval backend (frame::interval_backend_name) and the device memory it holds
  // beyond the mesh and the targets (the compute backend's pairs, per-cell bins, tile ranges
  // and sort scratch; 0 for the mesh backend).
  std::string backend = "mesh";
  uint64_t backend_bytes = 0;
  // The compute backend's counts, known once the frame finished (offscreen frames): the
  // (tile, cell) pairs drawn, and colour pixels whose intervals arrived too far out of order
  // for the k-buffer (composited in arrival order past it, so not exact).
  bool counts_known = false;
  uint64_t pairs = 0;
  uint64_t inexact_pixels = 0;
  // Cells binned by a workgroup each (their bounds span many tiles), and tiles whose long lists
  // were rastered in chunks and merged (ComputeIntervalStats).
  uint64_t big_cells = 0;
  uint64_t split_tiles = 0;
  uint64_t chunks = 0;
  uint64_t redone_tiles = 0;  // split tiles whose colour was rastered again whole, to keep each pixel's order
};

struct OffscreenFrame {
  uint32_t width = 0, height = 0;
  std::vector<float> quantity;  // one value per pixel, row 0 at the top
  std::vector<float> display;   // linear RGBA per pixel
  std::vector<float> emission;  // colour: premultiplied RGB and alpha per pixel; isosurface: shaded
                                // RGB and the distance from the eye to the hit (0: none)
  std::vector<vk::PassTiming> passes;
  FrameReport report;
};

}  // namespace prismoid::frame
