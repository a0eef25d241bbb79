#pragma once
// One frame of a scene, recorded the same way for the window and for offscreen images: the
// frame planner (frame_plan.hpp) decides the passes, prepare() runs its CPU passes and
// record() records exactly its GPU passes.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/frame/frame_units.hpp"
#include "renderer/vk/timer.hpp"
#include "renderer/volume/float_limits.hpp"
#include "renderer/volume/interval_shading.hpp"
#include "renderer/volume/resolve_pass.hpp"
#include "renderer/volume/volume_inputs.hpp"
#include "scene/bounds.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::volume {
class ComputeIntervals;
class VisibilitySort;
}  // namespace prismoid::volume

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

class FrameRenderer {
 public:
  FrameRenderer(const vk::Device& device, const TetMesh& mesh);
  ~FrameRenderer();

  // (Re)creates the targets when the size changes.
  void resize(VkExtent2D extent);
  VkExtent2D extent() const { return targets_.extent; }

  // What this renderer's scene contains for a frame with these settings from this camera,
  // with what changed since the last frame it recorded.
  SceneContents scene_contents(const Camera& camera, const FrameSettings& settings) const;
  // Plans the frame and runs the plan's CPU passes (pre-integration table, tetlets, exact
  // visibility order), outside any command buffer, with no frame of this renderer in flight.
  // Throws InputError for a frame float32 cannot represent (volume::check_float_limits, at the
  // targets' current size).
  FrameReport prepare(const Camera& camera, const FrameSettings& settings);
  // Records exactly the GPU passes prepare() planned, for the same camera and settings; the
  // display and quantity images end in TRANSFER_SRC layout.
  void record(VkCommandBuffer cmd, const Camera& camera, const FrameSettings& settings, vk::GpuTimer& timer);
  const vk::Image& display() const { return targets_.display; }
  const vk::Image& quantity() const { return targets_.quantity; }

  // The next frame plans as a first frame: nothing of the last one is reused (benchmarks time
  // what a moving camera's frame costs). Tables and tetlets, which depend on no camera, stay.
  void forget_history();

  // Prepares, renders, waits, reads the images back and returns them with the timings.
  OffscreenFrame render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent);
  // The same frame without reading its images back (the returned frame holds timings and the
  // report only): what the timed frames of `render --frames` and the bench run. Reading a 4K
  // frame back took longer than drawing it, and the H200 dropped to its idle clock in the gaps.
  OffscreenFrame render_timed(const Camera& camera, const FrameSettings& settings, VkExtent2D extent);

  const Bounds& bounds() const { return bounds_; }
  // The units the GPU draws in (frame_units.hpp): cameras and settings are given in world
  // units and converted; the mesh was uploaded in them.
  const FrameUnits& units() const { return units_; }
  const volume::IntervalShadingPass& interval_pass() const { return interval_; }
  // What both backends read (the transfer function and its table, a marched grid, the depth limit).
  const volume::VolumeInputs& volume_inputs() const { return inputs_; }
  // The compute backend; nullptr until a frame chose it.
  const volume::ComputeIntervals* compute_intervals() const { return compute_.get(); }
  // The GPU visibility sort; nullptr until a frame planned a sort (for tests: its pipelines
  // exist, and can be bound, only once one did).
  const volume::VisibilitySort* gpu_sort() const;

 private:
  struct Orderings;
  FrameRenderer(const vk::Device& device, const TetMesh& world, const FrameUnits& units);
  FrameRenderer(const vk::Device& device, const TetMesh& world, const FrameUnits& units, const TetMesh& local);
  // The settings in the GPU's units; the scaled depth limit is kept while the same one is given.
  FrameSettings local_settings(const FrameSettings& settings) const;

  const vk::Device& device_;
  FrameUnits units_;
  mutable std::shared_ptr<const std::vector<float>> limit_world_, limit_local_;
  volume::GpuTetMesh mesh_;
  Bounds bounds_;
  volume::MeshFloatFacts float_facts_;
  volume::VolumeInputs inputs_;
  volume::IntervalShadingPass interval_;
  std::unique_ptr<volume::ComputeIntervals> compute_;
  volume::ResolvePass resolve_;
  std::unique_ptr<Orderings> orderings_;
  struct Recorded;  // what the last recorded frame left behind
  std::unique_ptr<Recorded> recorded_;
  std::optional<FramePlan> plan_;  // prepare()'s plan, for the next record()
  glm::dvec3 plan_eye_{0.0};
  volume::VolumeTargets targets_;
  vk::GpuTimer offscreen_timer_;
};

}  // namespace prismoid::frame
