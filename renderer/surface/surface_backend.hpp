#pragma once
// The small interface every surface backend implements (one folder each under renderer/surface/)
// and what the surface renderer gives it. A backend says, as plain data, what it needs from the
// device and what it records (SurfaceBackendInfo: its passes by role, for the frame planner, and
// its command-line options); it records exactly the passes the frame's plan lists; it reports
// what it shaded and the memory it holds. Adding a backend is a new folder with a
// SurfaceBackendInfo and a SurfaceBackend, plus one line in surface_modes.cpp's table.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/msa/meshlets.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::surface {

// A backend's options as `render` got them: the setting's name (the option without its dashes) -> value ("" for a flag).
using SurfaceOptions = std::map<std::string, std::string>;

// One option a backend's modes take on `render`'s command line. Three names mean the same to every
// backend that takes them and are read by the command itself: `shadows` (on|off; every backend
// takes it), `supersample` (K x K sub-pixel positions averaged) and `frames` (timed frames, median).
// One option of a backend's modes: the setting's name (setting_names.hpp; the CLI's --name), the
// form of its value, and what it does with its default, for each front end's help.
struct SurfaceOption {
  std::string_view name;
  bool flag = false;       // given alone; else with a value
  std::string_view value;  // the value's form ("on|off", "N"); empty for a flag
  std::string_view help;   // what it does, and its default
};

// Every GPU surface backend takes it: whether the lights' shadows are traced.
inline constexpr SurfaceOption kShadowsOption{
    "shadows", false, "on|off", "ray-traced shadows; on by default where the device traces rays and a light casts them"};

// What the planner reads of a scene (no GPU: `info --plan` plans with it too): its triangles,
// lights, emissive triangles (those of emissive materials with a non-zero area, as upload()
// makes emitters of) and whether its sky is black.
frame::SurfaceContents surface_contents(const SurfaceScene& scene);

// The scene, its upload and its acceleration structure (built on first use), shared by every
// backend of one SurfaceRenderer.
class SharedSurfaceScene {
 public:
  // `scene` must already have its lights (with_default_lighting); uploaded now.
  SharedSurfaceScene(const vk::Device& device, const SurfaceScene& scene);
  ~SharedSurfaceScene();
  const vk::Device& device() const { return device_; }
  const SurfaceScene& scene() const { return scene_; }
  const GpuSurfaceScene& gpu() const { return gpu_; }
  // The TLAS of the scene relative to gpu().origin (rt::SceneAccel's default origin).
  const rt::SceneAccel& accel();
  frame::SurfaceContents contents() const { return contents_; }

 private:
  const vk::Device& device_;
  SurfaceScene scene_;
  GpuSurfaceScene gpu_;
  frame::SurfaceContents contents_;
  std::unique_ptr<rt::SceneAccel> accel_;
};

// Shading-rate controls a window or the bench sets at run time, each honoured by the backends
// that have it; unset ones leave a backend's option (or default) in force.
struct SurfaceTuning {
  std::optional<float> lod_bias;          // texture-space level-of-detail bias: +1 halves the texels per side
  std::optional<uint32_t> block_budget;   // block texels per frame (0: none)
  uint32_t amortize_every = 0;            // shade held samples again only every n-th frame (0: by the eye rule)
  std::optional<msa::Parametrization> msa_charts;  // the meshlet shading atlas's charts
};

// One frame to record.
struct BackendFrame {
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  const Camera& camera;
  VkExtent2D extent{};
  vk::GpuTimer& timer;
  const frame::FramePlan& plan;  // record exactly its GPU passes
  frame::SurfaceGi gi = frame::SurfaceGi::None;  // the mode's indirect light
  bool shadows = false;   // the plan traces shadow rays
  bool indirect = false;  // the plan runs GI passes
  const SurfaceTuning& tuning;
  glm::dvec2 subpixel{0.0};  // where each pixel is sampled (backends taking `supersample`)
};

// A value of a backend's stats (the JSON file of `render --stats`).
using StatValue = std::variant<bool, int64_t, uint64_t, double, std::string>;
using StatFields = std::vector<std::pair<std::string, StatValue>>;

// What the last frame did, read after its submission completed.
struct BackendCounts {
  uint64_t shaded = 0;        // shading-code invocations: pixels or texels (shaded_what)
  std::string shaded_what;    // "pixels" or "texels"
  // The stats field that sums `shaded` over the sub-pixel frames of a supersampled image
  // (forward: "fragments" or "shading_invocations"); empty: none.
  std::string shaded_field;
  uint64_t mode_bytes = 0;    // the backend's memory beyond the scene (atlas, pool, tables, reservoirs)
  std::string detail;         // one line for the window's panel
  std::string space;          // its shading space for `render`'s first line ("htex atlas 96x64 texels"); empty: none
  std::vector<std::string> summary;  // `render`'s lines after "covered: N pixels" (the first continues that line)
  StatFields stats;           // its settings and counters for --stats
};

class SurfaceBackend {
 public:
  virtual ~SurfaceBackend() = default;
  // Records exactly frame.plan's GPU passes, in order, each timed by frame.timer under its
  // name (SurfaceRenderer checks), leaving display() in TRANSFER_SRC_OPTIMAL.
  virtual void record(const BackendFrame& frame) = 0;
  // The last recorded frame's colour: RGBA32F linear radiance, alpha = coverage.
  virtual const vk::Image& display() const = 0;
  // The last recorded frame's depth: D32 reversed z (view_depth.hpp), in
  // DEPTH_ATTACHMENT_OPTIMAL, readable (TRANSFER_SRC); what a volume's rays end at.
  virtual const vk::Image& depth() const = 0;
  // The image size changed: targets are made again at the next record.
  virtual void release_targets() = 0;
  // The next frame shades everything it shows, as after a moved eye (another mode drew in
  // between, a shading rate changed, or a benchmark times a moving camera's frame).
  virtual void forget_shading() {}
  // Indirect light's history: frames accumulated since it was last forgotten, and forgetting it.
  virtual uint32_t gi_frames() const { return 0; }
  virtual void reset_gi() {}
  // Frames of a still camera an offscreen image of a mode with this indirect light averages (GI
  // converging); 1: one frame.
  virtual uint32_t offscreen_frames(frame::SurfaceGi gi) const {
    (void)gi;
    return 1;
  }
  // The tuning changed (the GPU is idle: the window and the bench change it between frames).
  virtual void retune(const SurfaceTuning& tuning) {
    (void)tuning;
    forget_shading();
  }
  virtual BackendCounts read_counts() const = 0;
};

// The SurfaceTuning controls a backend honours (SurfaceBackendInfo::tuning), so that the window's
// keys and the bench's rows apply to the modes that have them.
enum TuningKnob : uint32_t {
  kTuneLodBias = 1u << 0,      // SurfaceTuning::lod_bias
  kTuneBlockBudget = 1u << 1,  // SurfaceTuning::block_budget
  kTuneAmortize = 1u << 2,     // SurfaceTuning::amortize_every
  kTuneCharts = 1u << 3,       // SurfaceTuning::msa_charts
};

// A backend as the mode table names it: plain data and three functions.
struct SurfaceBackendInfo {
  std::string_view name;          // its folder under renderer/surface/
  std::string_view needs;         // what it needs from the device, in words (help, `devices`)
  frame::SurfacePasses passes;    // what it records, by role (the planner's input)
  std::vector<SurfaceOption> options;  // its modes' options on `render`, with their help
  uint32_t tuning = 0;            // the TuningKnobs it honours
  // Empty when `device` can run it, else why not.
  std::string (*device_problem)(const vk::Device& device) = nullptr;
  // `render`'s options checked (InputError naming the option) and completed with the command's
  // defaults where they differ from the backend's own (the window's and the bench's).
  SurfaceOptions (*command_options)(SurfaceOptions given, frame::SurfaceGi gi) = nullptr;
  // A backend for `scene` with these options (none: its defaults); made on the mode's first frame.
  std::unique_ptr<SurfaceBackend> (*make)(SharedSurfaceScene& scene, const SurfaceOptions& options) = nullptr;
};

// The frame planner's rule for reusing texture-space shading from earlier frames: a sample's
// shading stays right while nothing it depends on changes. The lights, materials and geometry
// are fixed for a SurfaceRenderer; what can change is the mode, the shadows setting and the eye.
// Every term of the shading depends on the eye through wo, if only where a shading normal facing
// away from the eye is replaced by the geometric one (even a diffuse sphere's grazing texels
// change), so a moved eye shades again; a still eye (the view turned or zoomed, or nothing
// moved) keeps every resident sample's shading.
struct ShadingReuse {
  bool invalidate = false;  // shade every marked sample this frame
  std::string reason;
};
struct ReuseInputs {
  bool first_frame = true;        // no earlier frame of this mode
  bool settings_changed = false;  // the shadows setting changed since the last frame
  bool eye_moved = false;
  bool amortized = false;  // the mode refreshes its shading on its own schedule (msa's shade_every)
};
ShadingReuse plan_shading_reuse(const ReuseInputs& in);

// A backend's memory of its last frame for plan_shading_reuse.
class ReuseHistory {
 public:
  ShadingReuse plan(const Camera& camera, bool shadows, bool amortized = false) const;
  void recorded(const Camera& camera, bool shadows) {
    last_eye_ = camera.eye;
    last_shadows_ = shadows;
  }
  void forget() { last_eye_.reset(); }

 private:
  std::optional<glm::dvec3> last_eye_;
  bool last_shadows_ = false;
};

// Helpers for backends reading their options: the value of `name` as a positive (or any)
// finite number, or a whole number; InputError naming the option otherwise.
double option_number(const SurfaceOptions& options, const std::string& name, double otherwise, bool positive);
uint32_t option_uint(const SurfaceOptions& options, const std::string& name, uint32_t otherwise);
// One of `choices`, or InputError listing them.
std::string option_choice(const SurfaceOptions& options, const std::string& name, const std::string& otherwise,
                          const std::vector<std::string>& choices);

}  // namespace prismoid::surface
