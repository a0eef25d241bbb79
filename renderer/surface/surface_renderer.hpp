#pragma once
// One surface scene on the GPU and the backends that draw it, behind one call per frame: what
// `render`, the window and the bench all draw surface modes through. Each frame of a mode
// (surface_modes.hpp) is planned (frame::plan_surface_frame: the passes its backend runs for this
// scene, with reasons), recorded by the mode's backend (made on the mode's first frame: a mode
// never chosen costs nothing), and checked: the passes timed are the plan's.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/msa/meshlets.hpp"
#include "renderer/surface/surface_backend.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::surface {

class SurfaceRenderer {
 public:
  // `scene` must already have its lights (with_default_lighting); it is uploaded now. `options`:
  // render's options for the backends (each reads those it takes; none: their defaults). Throws
  // InputError for an invalid scene, vk::NoSuitableDevice when no surface mode can run.
  SurfaceRenderer(const vk::Device& device, const SurfaceScene& scene, SurfaceOptions options = {});
  ~SurfaceRenderer();

  // The GPU modes this device draws, in the table's order.
  const std::vector<std::string>& modes() const { return modes_; }
  // Empty when `mode` can be drawn, else why not.
  std::string mode_problem(const std::string& mode) const;

  // Shadows: ray-traced where the device traces rays (can_shadow); on by default there when the
  // scene has a light that casts them. set_shadows(true) without can_shadow() throws
  // vk::NoSuitableDevice. The acceleration structure is built on first use.
  bool can_shadow() const;
  bool shadows() const { return shadows_; }
  void set_shadows(bool on);

  // The image size of the next frames (targets are remade when it changes).
  void resize(VkExtent2D extent);
  VkExtent2D extent() const { return extent_; }

  // The plan of a frame of `mode` now (pure; InputError when mode_problem says no).
  frame::FramePlan plan(const std::string& mode) const;
  // Records one frame of `mode`: exactly its plan's GPU passes (std::logic_error otherwise).
  // Leaves display() in TRANSFER_SRC_OPTIMAL: linear RGBA32F radiance, alpha = coverage.
  void record(VkCommandBuffer cmd, const Camera& camera, const std::string& mode, vk::GpuTimer& timer);
  const vk::Image& display() const;
  // The last frame's depth buffer (SurfaceBackend::depth): view_depth.hpp reads it back.
  const vk::Image& depth() const;
  // The plan the last record() carried out.
  const frame::FramePlan& last_plan() const { return last_plan_; }

  // What the last frame shaded, read after its submission completed (the window reads it once
  // the frame's fence has signalled): shading-code invocations (pixels for forward, texels for
  // the texture-space modes), the mode's own memory beyond the scene, a line for the panel, and
  // render's report of it.
  using FrameCounts = BackendCounts;
  FrameCounts read_counts() const;

  // One image of `mode` read back (what `render` writes): the mean of `supersample` x
  // `supersample` sub-pixel positions (backends taking `supersample`) and, for a GI mode, of the
  // backend's offscreen frames of the still camera; alpha the mean coverage of the last of them.
  // Passes: the last still frame's, summed over the sub-pixel positions; counts: the last
  // frame's, with `shaded` summed over the sub-pixel positions.
  struct Offscreen {
    uint32_t width = 0, height = 0;
    std::vector<float> rgba;
    std::vector<vk::PassTiming> passes;
    FrameCounts counts;
    frame::FramePlan plan;
  };
  Offscreen render_offscreen(const Camera& camera, const std::string& mode, VkExtent2D extent, uint32_t supersample = 1);

  // Frames of GI accumulated by the last mode's backend since its history was last forgotten (the
  // bench lets them accumulate), and forgetting every backend's.
  uint32_t gi_frames() const;
  void reset_gi();
  // The next frame shades every sample it shows, as after a moved eye (the bench times each
  // frame as a moving camera's).
  void forget_shading();

  // Shading rate of the texture-space modes: a level-of-detail bias (+1 halves the texels per
  // side) for the backends with kTuneLodBias, a block-texel budget per frame (0: none) for those
  // with kTuneBlockBudget. Shades afresh.
  void set_shading_rate(float lod_bias, uint32_t block_budget);
  // Temporal amortization (kTuneAmortize; Neff et al. 2022): with n > 0 a moving eye no longer
  // shades held samples again; every n-th frame does, and in between only new ones are shaded.
  // 0: every moved eye shades again.
  void set_msa_amortization(uint32_t every_n_frames);
  uint32_t msa_amortization() const { return tuning_.amortize_every; }
  // The meshlets' charts (kTuneCharts): a change rebuilds the meshlets and the atlas (the GPU
  // must be idle: the bench and the window call it between frames).
  void set_msa_charts(msa::Parametrization charts);
  msa::Parametrization msa_charts() const;

  const vk::Device& device() const { return device_; }
  const GpuSurfaceScene& gpu_scene() const { return shared_.gpu(); }
  const SurfaceScene& scene() const { return shared_.scene(); }

 private:
  const SurfaceMode& drawable(const std::string& mode) const;
  SurfaceBackend& backend(const SurfaceMode& mode);
  void retune();

  const vk::Device& device_;
  SharedSurfaceScene shared_;
  SurfaceOptions options_;
  std::vector<std::string> modes_;
  std::map<const SurfaceBackendInfo*, std::unique_ptr<SurfaceBackend>> backends_;
  VkExtent2D extent_{1, 1};
  bool shadows_ = false;
  SurfaceTuning tuning_;
  glm::dvec2 subpixel_{0.0};
  const SurfaceBackend* last_backend_ = nullptr;
  std::string last_mode_;
  frame::FramePlan last_plan_;
};

}  // namespace prismoid::surface
