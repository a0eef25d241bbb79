#pragma once
// One surface scene on the GPU and the backends that draw it, behind one call per frame: what
// the window, the bench and the CLI use to switch between surface modes. Each backend is made
// on first use (a mode never chosen costs nothing) and shades with the same code and buffers.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/htex/htex_pass.hpp"
#include "renderer/surface/gi/htex_gi.hpp"
#include "renderer/surface/htex/htex_tables.hpp"
#include "renderer/surface/msa/msa_pass.hpp"
#include "renderer/surface/texel/texel_pass.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::surface {

// Htex's finest level: this many texels along the scene's bounding-box diagonal on its largest
// quads (texels_per_unit = this / diagonal), so the finest level is about two texels per pixel
// for the whole scene seen in a 1080p view; the level of detail picks coarser levels from
// there. The size follows the scene, not its units (a scene in millimetres gets the same atlas
// as one in metres).
inline constexpr double kHtexTexelsPerDiagonal = 2048.0;
// The GI modes' pool: GI keeps 256 bytes per pool texel (samples, reservoirs, stamps), 16 times
// the pool's own 16, so 256 pages of 4096 texels hold 16 MiB of radiance and 256 MiB of GI.
inline constexpr uint32_t kGiPoolPages = 256;
double htex_texels_per_unit(const SurfaceScene& scene);

// The frame planner's rule for reusing Htex shading from earlier frames (HtexSettings::
// reuse_shading): a shadel's shaded texels stay right while nothing they depend on changes. The
// lights, materials and geometry are fixed for a SurfaceRenderer; what can change is the mode,
// the shadows setting and the eye. Every term of the shading depends on the eye through wo, if
// only where a shading normal facing away from the eye is replaced by the geometric one (even a
// diffuse sphere's grazing texels change), so a moved eye shades again; a still eye (the view
// turned or zoomed, or nothing moved) keeps every resident shadel's shading.
struct ShadingReuse {
  bool invalidate = false;  // shade every marked shadel this frame
  std::string reason;
};
struct ReuseInputs {
  bool first_frame = true;        // no earlier frame of this mode
  bool settings_changed = false;  // the shadows setting changed since the last frame
  bool eye_moved = false;
  bool amortized = false;  // the mode refreshes its shading on its own schedule (msa's shade_every)
};
ShadingReuse plan_shading_reuse(const ReuseInputs& in);

// The surface modes this device can draw, in the order the window lists them: forward (per
// pixel, renderer/surface/forward/forward_pass and shadowed_forward_pass), htex (object space,
// renderer/surface/htex/htex_pass), and Htex with one-bounce indirect light (renderer/surface/
// gi/htex_gi): htex-gi (ReSTIR GI as the paper ships it, biased), htex-gi-unbiased (the
// bias-corrected combination) and htex-pt (one bounce sample per texel and frame, no reuse: plain
// path tracing in object space, the baseline ReSTIR is measured against), then texel (texel
// shading over a static atlas, renderer/surface/texel/texel_pass) and msa (the meshlet shading atlas,
// renderer/surface/msa/msa_pass).
std::vector<std::string> surface_modes(const vk::Device& device);

class SurfaceRenderer {
 public:
  // `scene` must already have its lights (with_default_lighting); it is uploaded now. Throws
  // InputError for an invalid scene, vk::NoSuitableDevice when no surface mode can run.
  SurfaceRenderer(const vk::Device& device, const SurfaceScene& scene);
  ~SurfaceRenderer();

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

  // Records one frame of `mode` (InputError when mode_problem says no). Leaves display() in
  // TRANSFER_SRC_OPTIMAL: linear RGBA32F radiance, alpha = coverage.
  void record(VkCommandBuffer cmd, const Camera& camera, const std::string& mode, vk::GpuTimer& timer);
  const vk::Image& display() const;

  // What the last frame shaded, read after its submission completed (the window reads it once
  // the frame's fence has signalled): shading-code invocations (pixels for forward, texels for
  // htex) and the mode's own memory beyond the scene (htex: pool and tables).
  struct FrameCounts {
    uint64_t shaded = 0;
    uint64_t mode_bytes = 0;
    std::string detail;  // a line for the panel and reports (htex: shadels, pages, bias)
  };
  FrameCounts read_counts() const;

  // The GI modes' settings for `mode` (htex-gi, htex-gi-unbiased, htex-pt).
  static RestirGiSettings gi_settings(const std::string& mode);
  // Frames of GI since its reservoirs were last forgotten (the bench lets them accumulate).
  uint32_t gi_frames() const { return gi_frame_; }
  void reset_gi();
  // The next htex (texel) frame shades every marked shadel (queued tile), as after a moved eye
  // (the bench times each frame as a moving camera's).
  void forget_shading() { last_eye_.reset(); }

  // Shading rate of the texture-space modes: a level-of-detail bias for htex and texel (+1 halves
  // the texels per side), a block-texel budget per frame for msa (0: none). Shades afresh.
  void set_shading_rate(float lod_bias, uint32_t msa_budget);
  // The meshlet shading atlas's temporal amortization (Neff et al. 2022): with n > 0 a moving
  // eye no longer shades msa's blocks again; every n-th frame does (MsaSettings::shade_every),
  // and in between only blocks new to the atlas are shaded. 0: every moved eye shades again.
  void set_msa_amortization(uint32_t every_n_frames);
  uint32_t msa_amortization() const { return msa_amortization_; }
  // The meshlets' charts (msa::Parametrization): a change rebuilds the meshlets and the atlas
  // (the GPU must be idle: the bench and the window call it between frames).
  void set_msa_charts(msa::Parametrization charts);
  msa::Parametrization msa_charts() const { return msa_charts_; }

  const GpuSurfaceScene& gpu_scene() const { return scene_; }
  const SurfaceScene& scene() const { return source_; }

 private:
  const vk::Device& device_;
  SurfaceScene source_;
  GpuSurfaceScene scene_;
  std::vector<std::string> modes_;
  VkExtent2D extent_{1, 1};
  bool shadows_ = false;
  std::unique_ptr<ForwardPass> forward_;
  std::unique_ptr<ForwardTargets> forward_targets_;
  std::unique_ptr<rt::SceneAccel> accel_;
  std::unique_ptr<ShadowedForwardPass> shadowed_;
  std::unique_ptr<ShadowedForwardTargets> shadowed_targets_;
  std::unique_ptr<HtexGeometry> htex_geometry_;
  std::unique_ptr<HtexPass> htex_;
  std::unique_ptr<HtexTargets> htex_targets_;
  std::unique_ptr<texel::TexelAtlas> texel_atlas_;
  std::unique_ptr<TexelPass> texel_;
  std::unique_ptr<TexelTargets> texel_targets_;
  std::unique_ptr<msa::MeshletSet> meshlets_;
  std::unique_ptr<MsaPass> msa_;
  std::unique_ptr<MsaTargets> msa_targets_;
  std::unique_ptr<HtexPass> gi_pass_;  // indirect buffer on, sky ambient off, its own pool
  std::unique_ptr<HtexGi> gi_;
  uint32_t gi_frame_ = 0;
  const vk::Image* display_ = nullptr;  // the last recorded frame's colour
  std::string last_mode_;
  std::optional<glm::dvec3> last_eye_;  // of the last htex, texel or msa frame
  bool last_shadows_ = false;
  float lod_bias_ = 0.0f;
  uint32_t msa_budget_ = 0;
  uint32_t msa_amortization_ = 0;
  msa::Parametrization msa_charts_ = msa::Parametrization::Projection;
  ShadingReuse last_reuse_;
  ShadingReuse plan_reuse(const Camera& camera, bool amortized = false) const;
  void record_texel(VkCommandBuffer cmd, const Camera& camera, vk::GpuTimer& timer);
  void record_msa(VkCommandBuffer cmd, const Camera& camera, vk::GpuTimer& timer);
  void record_htex_gi(VkCommandBuffer cmd, const Camera& camera, const std::string& mode, vk::GpuTimer& timer);
};

}  // namespace prismoid::surface
