#pragma once
// The renderer's one door (issue "One renderer for every front end"): a scene (a volume, surfaces,
// or a volume inside its surfaces) and settings in, a frame out. Whether a frame is drawn on the
// GPU or by a CPU reference, and by which backend, follows from the mode tables
// (frame::volume_mode_table, surface::surface_mode_table) and the backend tables behind them: the
// front end names modes, never a code path. The device is opened with the first frame that needs
// one, and the renderers made for the scene are kept for the frames after (a scene that persists,
// as the window will want).
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/mixed/frame_stats.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/reference/path_tracer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/timing/frame_timing.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::vk {
class Instance;
class Device;
}  // namespace prismoid::vk

namespace prismoid::mixed {

// The GPU frames' device, opened with the first frame that needs one.
struct DeviceRequest {
  bool validation = false;        // the Khronos validation layer, its messages logged (instance())
  std::optional<uint32_t> index;  // vk::select_device's choice; none: the first suitable device
};

// What the frames draw: a volume, surfaces, or both. The renderer keeps the pointers: the data
// must outlive it.
struct SceneData {
  const TetMesh* volume = nullptr;
  bool analytic_field = false;             // the volume samples an analytic field: its CPU reference marches the field
  const SurfaceScene* surfaces = nullptr;  // with its lights already (with_default_lighting)
  bool default_lighting = false;           // those lights are the default ones (the scene had none): said in the stats
};

// A sequence of surface frames as the bench times them (surfaces alone, on the GPU): the shading
// rate and tuning the texture-space backends take, the camera's motion, and how a GI mode gathers.
// Its frames are timed without reading an image back (the GPU stays busy and at its clock); the
// image is read once, after the last timed frame.
struct SurfaceSequence {
  float lod_bias = 0.0f;        // surface::SurfaceRenderer::set_shading_rate
  uint32_t block_budget = 0;
  uint32_t amortize = 0;        // set_msa_amortization; counted from the camera path's first frame
  msa::Parametrization charts = msa::Parametrization::Projection;  // set_msa_charts
  // A moving camera: frame i's camera; `frames` untimed frames along it, then the timed ones,
  // the last at index 2 * frames - 1. None: the camera render() is given.
  std::function<Camera(uint32_t frame)> camera_path;
  // Frames of a still camera reuse its shading (none forgotten between them). Without it, and
  // without a camera path or indirect light, each timed frame shades afresh (a moving camera's cost).
  bool keep_shading = false;
  // A GI mode's reservoirs start afresh after the warm-up and gather over this many frames of the
  // still camera, the timed frames last (at least `frames`).
  uint32_t gi_frames = 0;
};

struct SceneSettings {
  VkExtent2D size{800, 600};
  // The volume's mode (a row of frame::volume_mode_table()) and its frame's settings.
  const frame::VolumeMode* volume_mode = nullptr;
  frame::FrameSettings volume;
  bool volume_backend_auto = false;  // volume.backend is chosen on the device (SceneRenderer's AutoBackend)
  // The surfaces' mode (a row of surface::surface_mode_table()), its backend's options, and whether
  // they cast shadows (none: the surface renderer's default, on where the device traces rays and a
  // light casts them).
  const surface::SurfaceMode* surface_mode = nullptr;
  surface::SurfaceOptions surface_options;
  std::optional<bool> shadows;
  uint32_t supersample = 1;            // surfaces alone, on the GPU: the mean of k x k sub-pixel positions
  reference::PathTracerSettings path;  // surfaces alone, by the CPU path tracer (its size is `size`)
  // GPU frames are timed: `frames` of them, each costing what a moving camera's does (no order or
  // shading kept from the one before), after at least `warm_up_seconds` of untimed ones
  // (timing::warm_up says why). None given: timing::kTimedWarmUpSeconds where frames > 1, no
  // warm-up for one frame.
  uint32_t frames = 1;
  std::optional<double> warm_up_seconds;
  // An interactive frame (the ParaView plugin's, the window's): drawn once, timed only by its own
  // passes' timestamps, and reusing what the renderers kept from the frame before where the planner
  // allows it (a still camera's order, a still view's shading). `frames` and the warm-up are unused.
  bool interactive = false;
  // Surfaces alone on the GPU: frames timed as a sequence of the bench's (none: each timed frame
  // read back, shading afresh, as `render --frames` times them).
  std::optional<SurfaceSequence> sequence;
};

// One frame: what drew it and what it drew. Exactly one of volume, surfaces, path and mixed holds
// the images, by the scene and the modes.
struct SceneFrame {
  std::string device, driver;  // the GPU's name and driver, or which CPU reference drew it
  bool gpu = false;
  frame::FrameSettings volume_settings;       // as drawn: an `auto` backend resolved, with its reason
  std::optional<timing::FrameTiming> timing;  // timed GPU frames: each pass's spread over them (the images' passes hold the medians)
  std::vector<double> frame_cpu_ms;           // timed volume frames: each one's CPU passes, summed
  std::vector<uint64_t> frame_shaded;         // timed surface sequences: each frame's shading invocations
  std::optional<frame::OffscreenFrame> volume;                   // a volume alone
  std::optional<surface::SurfaceRenderer::Offscreen> surfaces;   // surfaces alone, on the GPU
  std::optional<reference::PathTracedImage> path;                // surfaces alone, by the path tracer
  std::optional<MixedFrame> mixed;                               // a volume inside its surfaces
  FrameStats stats;  // render()'s frames: every counter, setting and time above, typed (frame_stats.hpp)
};

// Chooses the backend of `--volume-backend auto` on a device (the CLI keeps its calibrations in a
// cache file): sets settings.backend and settings.backend_reason.
using AutoBackend = std::function<void(frame::FrameSettings& settings, const vk::Device& device)>;

// What the renderer has sent to the GPU for the scene's volume: whole meshes (points, cells and
// fields) and fields alone (time steps of a static mesh, SceneRenderer::set_volume).
struct VolumeUploads {
  uint32_t meshes = 0;
  uint32_t fields = 0;
};

class SceneRenderer {
 public:
  SceneRenderer(SceneData scene, DeviceRequest device, AutoBackend auto_backend = {});
  // Frames on a device the caller opened and keeps (the bench's, the window's, a test's).
  SceneRenderer(SceneData scene, const vk::Device& device, AutoBackend auto_backend = {});
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  // One frame of `settings` from `camera`, timed as SceneSettings says. InputError for settings the
  // scene's modes refuse; vk::NoSuitableDevice where the device cannot draw them.
  SceneFrame render(const Camera& camera, const SceneSettings& settings);

  // The same frame by its CPU double-precision reference (the image `render --reference-error`
  // measures against): a volume's in exact order, a mixed scene's with the surfaces' direct light
  // (shadows as `drawn` had them). `drawn` is a frame render() returned for this scene. Surfaces
  // alone have the path tracer, a mode of their own: std::logic_error.
  SceneFrame reference(const Camera& camera, const SceneSettings& settings, const SceneFrame& drawn) const;

  // The volume the next frames draw instead (a scene with a volume only): a time step. Where its
  // points and cells are those of the volume drawn so far (compared, never assumed), only its
  // fields go to the GPU and what depends on the geometry alone is kept (frame::FrameRenderer::
  // update_fields); otherwise the next GPU frame uploads it whole. No frame may be in flight.
  // A step whose fields are invalid (validate) throws, and no renderer keeps the step before.
  void set_volume(const TetMesh& volume);
  VolumeUploads volume_uploads() const { return uploads_; }

  // The instance, once a GPU frame opened it (its validation log); nullptr before and for a
  // caller's device.
  const vk::Instance* instance() const { return instance_.get(); }
  // The GPU surface scene of surfaces alone, once a GPU frame uploaded it; nullptr before.
  const surface::GpuSurfaceScene* gpu_surfaces() const { return surfaces_ ? &surfaces_->gpu_scene() : nullptr; }
  // The surface renderer of surfaces alone with these backend options (made, and the device
  // opened, on the first call): what it draws (modes(), can_shadow()) before any frame. Each set of
  // options keeps a renderer of its own (a backend's options are fixed at its making).
  const surface::SurfaceRenderer& surface_renderer(const surface::SurfaceOptions& options = {});

 private:
  const vk::Device& device();
  SceneFrame render_volume(const Camera& camera, const SceneSettings& settings);
  SceneFrame render_surfaces(const Camera& camera, const SceneSettings& settings);
  void render_surface_sequence(SceneFrame& f, const Camera& camera, const SceneSettings& settings);
  surface::SurfaceRenderer& surfaces_for(const surface::SurfaceOptions& options);
  SceneFrame render_mixed(const Camera& camera, const SceneSettings& settings);
  void gpu_identity(SceneFrame& f) const;
  // f.stats from the frame's images and the renderers that drew it.
  void fill_stats(SceneFrame& f, const SceneSettings& settings) const;
  // Sets `volume`'s backend where the settings ask for the automatic one (std::invalid_argument
  // without an AutoBackend).
  void resolve_auto(frame::FrameSettings& volume, const SceneSettings& settings, const vk::Device& device) const;

  SceneData scene_;
  DeviceRequest request_;
  AutoBackend auto_backend_;
  std::unique_ptr<vk::Instance> instance_;
  std::string device_name_, driver_;
  std::unique_ptr<vk::Device> owned_device_;
  const vk::Device* device_ = nullptr;
  std::unique_ptr<frame::FrameRenderer> volume_;
  std::map<surface::SurfaceOptions, std::unique_ptr<surface::SurfaceRenderer>> surface_renderers_;
  surface::SurfaceRenderer* surfaces_ = nullptr;  // the last frame's
  std::unique_ptr<MixedRenderer> mixed_;
  VolumeUploads uploads_;
};

}  // namespace prismoid::mixed
