#pragma once
// One frame of a scene, recorded the same way for the window and for offscreen images: the
// frame planner (frame_plan.hpp) decides the passes, prepare() runs its CPU passes and
// record() records exactly its GPU passes. What every backend reads (VolumeInputs) and the
// resolve are the renderer's; the intervals are drawn by the GPU backend the settings name,
// from the volume backend table (renderer/volume/volume_backends.hpp), made on first use.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/frame/frame_report.hpp"
#include "renderer/frame/frame_units.hpp"
#include "renderer/vk/timer.hpp"
#include "renderer/volume/float_limits.hpp"
#include "renderer/volume/resolve_pass.hpp"
#include "renderer/volume/volume_backend.hpp"
#include "renderer/volume/volume_inputs.hpp"
#include "scene/bounds.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::volume {
class ComputeIntervals;
class VisibilitySort;
}  // namespace prismoid::volume

namespace prismoid::frame {

class FrameRenderer {
 public:
  FrameRenderer(const vk::Device& device, const TetMesh& mesh);
  ~FrameRenderer();

  // (Re)creates the targets when the size changes.
  void resize(VkExtent2D extent);

  // A time step of a static mesh: where `mesh`'s points and cells are those this renderer draws
  // (compared, never assumed), only its fields (extinction, scalars) are uploaded, and what depends
  // on the geometry alone is kept: the buffers of points and cells, the mesh backend's adjacency,
  // tetlets and a still camera's visibility order. Returns false, changing nothing, where the
  // geometry differs (the caller then makes a renderer of the new mesh). Waits for the device.
  bool update_fields(const TetMesh& mesh);
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
  // What every backend reads (the transfer function and its table, a marched grid, the depth limit).
  const volume::VolumeInputs& volume_inputs() const { return inputs_; }
  // The draw counts of the last finished frame, where its backend counts draws (the window's panel).
  std::optional<volume::DrawCounts> draw_counts() const;
  // The GPU backend of that name; nullptr until a frame chose it.
  const volume::GpuVolumeBackend* backend(std::string_view name) const;
  // For tests: the compute backend's passes, and the mesh backend's GPU visibility sort (its
  // pipelines exist, and can be bound, only once a frame planned a sort); nullptr until made.
  const volume::ComputeIntervals* compute_intervals() const;
  const volume::VisibilitySort* gpu_sort() const;

 private:
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
  volume::ResolvePass resolve_;
  // The scene as the backends read it, and the backends made so far (by name).
  std::unique_ptr<TetMesh> geometry_;  // points and cells in the GPU's units
  bool point_extinction_ = false, point_scalars_ = false;  // what the mesh's fields are (for the planner)
  std::map<std::string, std::unique_ptr<volume::GpuVolumeBackend>, std::less<>> backends_;
  volume::GpuVolumeBackend* active_ = nullptr;  // the backend of the frame prepare() planned (then recorded)
  // The backend the settings name, made on first use.
  volume::GpuVolumeBackend& backend_for(const FrameSettings& settings);
  struct Recorded;  // what the last recorded frame left behind
  std::unique_ptr<Recorded> recorded_;
  std::optional<FramePlan> plan_;  // prepare()'s plan, for the next record()
  glm::dvec3 plan_eye_{0.0};
  volume::VolumeTargets targets_;
  vk::GpuTimer offscreen_timer_;
};

}  // namespace prismoid::frame
