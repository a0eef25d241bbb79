#pragma once
// The small interface every volume backend implements (one folder each under renderer/volume/)
// and what the frame renderer gives it, as surface_backend.hpp is for surfaces. A backend says,
// as plain data, what it draws and what it needs from the device (VolumeBackendInfo); a GPU
// backend runs the plan's CPU passes that are its own, records exactly the plan's GPU passes
// that are its own (the shared inputs and the resolve are the renderer's), and reports what it
// drew. The CPU reference is a backend too: it draws a whole frame without a device. Adding a
// backend is a new folder with a VolumeBackendInfo, plus one line in volume_backends.cpp's table.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/frame/frame_report.hpp"
#include "renderer/frame/volume_passes.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/volume/resolve_pass.hpp"
#include "renderer/volume/volume_inputs.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::vk {
class Device;
class GpuTimer;
}  // namespace prismoid::vk

namespace prismoid::volume {

// What a GPU backend draws from, for the life of its FrameRenderer (in the GPU's units).
struct BackendScene {
  const vk::Device& device;
  const GpuTetMesh& mesh;
  const TetMesh& geometry;  // the points and cells only (the CPU's visibility order and tetlets read them)
};

// One frame being prepared: outside any command buffer, no frame of the renderer in flight.
struct BackendPrepare {
  const Camera& camera;                  // in the GPU's units
  const frame::FrameSettings& settings;  // in the GPU's units
  VkExtent2D extent{};
};

// One frame being recorded.
struct BackendRecord {
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  const Camera& camera;
  const frame::FrameSettings& settings;
  const VolumeInputs& inputs;
  VolumeTargets& targets;
  vk::GpuTimer& timer;
};

// What the last recorded frame left in device memory that the planner may reuse.
struct BackendHistory {
  std::optional<frame::Ordering> order_kept;  // the ordering that made the order buffer it drew with
  bool tetlets_built = false;                 // tetlets of the settings' size exist
};

// Draw counts of the last frame (pipeline statistics), where the backend counts them.
struct DrawCounts {
  uint64_t primitives = 0;  // proxy triangles that reached the rasterizer's clipper
  uint64_t fragments = 0;   // fragment-shader invocations: (pixel, segment) pairs shaded
};

class GpuVolumeBackend {
 public:
  virtual ~GpuVolumeBackend() = default;
  // Checks the settings and makes pipelines, before the frame is planned; InputError names the
  // setting at fault.
  virtual void check(const BackendPrepare& frame) = 0;
  virtual BackendHistory history(const frame::FrameSettings& settings) const = 0;
  // Runs one of the plan's CPU passes that is this backend's (false: not one of its passes).
  virtual bool run_cpu(const frame::PlannedPass& pass, const BackendPrepare& frame) = 0;
  // After the CPU passes: what the frame's report says of the backend (the order its
  // intervals are composited in, the memory it holds).
  virtual void prepared(const BackendPrepare& frame, const frame::FramePlan& plan, frame::FrameReport& report) = 0;
  // Records one of the plan's GPU passes that is this backend's, timed under the pass's name
  // (false: not one of its passes).
  virtual bool record(const frame::PlannedPass& pass, const BackendRecord& frame) = 0;
  // How its passes left the accumulation targets for the resolve.
  virtual AccumulatedBy accumulated_by() const = 0;
  // The frame recorded last was drawn by this backend with these settings.
  virtual void recorded(const frame::FrameSettings& settings) = 0;
  // The next frame plans as a first frame (nothing of the last one reused).
  virtual void forget_history() = 0;
  // After an offscreen frame finished: its counts into the report; false when the frame drew
  // only part of its work and must be drawn again (its next prepare() makes room).
  virtual bool finished(const frame::FrameSettings& settings, frame::FrameReport& report) = 0;
  // The last frame's draw counts, where the backend counts draws (the window's panel).
  virtual std::optional<DrawCounts> draw_counts() const { return std::nullopt; }
};

// What a backend draws, for the refusals (whether it draws cells in the mode's order and builds
// tetlets is its VolumePasses').
struct VolumeSupport {
  bool march = false;        // samples a non-linear field inside intervals (and isosurfaces of it)
  bool depth_limit = false;  // rays end at opaque geometry (mixed scenes)
};

// A backend as the table names it: plain data and the functions that make or run it.
struct VolumeBackendInfo {
  std::string_view name;      // its folder under renderer/volume/ and --volume-backend's word
  std::string_view summary;   // one line for the help and `devices`
  std::vector<vk::Feature> needs;  // what it needs from the device (none: it runs on the CPU)
  VolumeSupport supports;
  frame::VolumePasses passes;  // GPU backends: its part of a frame, for the planner
  // GPU backends: one for a FrameRenderer's scene, made on the first frame that asks for it.
  std::unique_ptr<GpuVolumeBackend> (*make)(const BackendScene& scene) = nullptr;
  // CPU backends: the whole frame, in world units, of the mesh's field or (`field`) of the
  // analytic field the settings march.
  frame::OffscreenFrame (*render)(const TetMesh& mesh, const Camera& camera, const ResolveSettings& settings, VkExtent2D size,
                                  bool field) = nullptr;
  bool gpu() const { return make != nullptr; }
};

}  // namespace prismoid::volume
