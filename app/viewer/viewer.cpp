#include "app/viewer/viewer.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "app/common/backend_cache.hpp"
#include "app/viewer/dataset_list.hpp"
#include "app/viewer/compare_panel.hpp"
#include "app/viewer/compare_view.hpp"
#include "app/viewer/interactive_scale.hpp"
#include "app/viewer/window_input.hpp"
#include "app/viewer/window_loop.hpp"
#include "app/viewer/viewer_session.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/volume/mesh/interval_shading.hpp"
#include "scene/coarse_proxy.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

// Runs the script's commands that are due, unless a wait-reference holds them.
void run_script(ViewerSession& s, const CompareView& compare, const std::vector<ScriptCommand>& script, size_t& next) {
  if (s.reference_deadline) {
    if (compare.reference_settled()) {
      s.reference_deadline.reset();
    } else if (std::chrono::steady_clock::now() > *s.reference_deadline) {
      s.message("wait-reference: timed out");
      s.reference_deadline.reset();
    } else {
      return;
    }
  }
  if (script_waiting(s)) return;  // wait-load holds the script's clock too
  auto held = [&] { return s.reference_deadline.has_value() || s.loading.script_deadline.has_value(); };
  for (; next < script.size() && script[next].frame <= s.script_frame && !held(); ++next) {
    try {
      s.run(script[next]);
    } catch (const InputError& e) {
      s.message(script[next].where + ": " + e.what());
    } catch (const std::exception& e) {  // whatever a command meets, the window goes on
      s.failed("Error", script[next].where + ": " + e.what());
    }
  }
  if (!held()) ++s.script_frame;
}

// The volume window's content in the shared frame loop: the FrameRenderer's planned frame
// (and split view's B) blitted to the swapchain, the side panel, HUD and compare overlay.
class VolumeWindow final : public WindowContent {
 public:
  VolumeWindow(ViewerSession& s, CompareView& compare, const std::vector<ScriptCommand>& script, uint32_t max_tetlet, double target_ms)
      : s_(s), compare_(compare), script_(script), max_tetlet_(max_tetlet), scale_(target_ms) {}

  CameraController& camera() override { return s_.camera; }
  bool show_ui() const override { return s_.state.show_ui; }
  void run_due() override {
    poll_loads(s_);
    poll_time(s_);
    run_script(s_, compare_, script_, next_command_);
  }
  void frame_started(double cpu_frame_ms) override { s_.stats.cpu_frame_ms = cpu_frame_ms; }
  void on_key(const KeyPress& key) override { s_.on_key(key); }
  void pointer_held(bool held) override { pointer_held_ = held; }
  void on_drop(const std::vector<std::string>& paths) override { open_datasets(s_, paths, s_.panel.data.array); }
  void frame_finished(std::vector<vk::PassTiming> passes, bool last) override {
    s_.stats.frame.passes = std::move(passes);
    finished_ms_ = 0.0;
    for (const vk::PassTiming& p : s_.stats.frame.passes)
      if (std::isfinite(p.gpu_ms)) finished_ms_ += p.gpu_ms;
    finished_level_ = in_flight_level_;
    // Each frame's wall time from its recording to its end, against its motion and resolution
    // (the scripted window run's numbers: docs/results.md).
    const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - recorded_at_).count();
    if (drawn_moving_) s_.report.moving_frames.push_back({wall_ms, in_flight_level_});
    else if (after_motion_) s_.report.still_frames_ms.push_back(wall_ms);
    after_motion_ = after_motion_ || drawn_moving_;
    if (!last)
      if (const auto counts = s_.renderer.draw_counts()) {
        frame::FrameReport& report = s_.stats.report();
        report.counted = true;
        report.fragments = counts->fragments;
        report.primitives = counts->primitives;
      }
    compare_.frame_finished();
  }
  std::string timings_line() const override {
    std::ostringstream title;
    title << "Prismoid - " << s_.stats.frame.device << " -";
    for (const auto& t : s_.stats.frame.passes) title << " " << t.name << " " << t.gpu_ms << " ms";
    return title.str();
  }
  void draw_ui() override {
    if (!s_.state.show_ui) return;
    const UiRequests requests = draw_side_panel(s_.state, s_.panel, s_.stats, s_.camera, max_tetlet_);
    draw_hud(s_.stats, s_.state);
    draw_compare_overlay(compare_.status(), s_.state, s_.stats);
    s_.apply(requests);
  }
  void prepare_frame(VkExtent2D extent) override {
    sync_renderer(s_);
    // While the camera moves (and no comparison needs the window's own size), the volume is drawn
    // at the resolution that holds the target frame time, and shown scaled up (interactive_scale.hpp).
    const Camera& now = s_.camera.camera();
    const bool moved = have_camera_ && (now.eye != last_camera_.eye || now.target != last_camera_.target || now.up != last_camera_.up ||
                                        now.fovy_degrees != last_camera_.fovy_degrees);
    last_camera_ = now;
    have_camera_ = true;
    scale_.allow_proxy(proxy_allowed());
    // A drag that pauses (a button held, the mouse still) keeps moving: its next motion should
    // not wait for a full frame; the release is what asks for one.
    scale_.update((moved || pointer_held_) && s_.state.compare == CompareMode::Off, finished_ms_, finished_level_);
    finished_ms_ = 0.0;  // each finished frame's time is given once
    if (scale_.proxy() && build_proxy(scale_.proxy_index(), s_.state.drawn().mesh)) ++s_.report.proxies_made_in_frames;
    if (scale_.proxy()) s_.stats.cells = proxies_[scale_.proxy_index()].mesh->tets.size();
    else if (s_.state.drawn().mesh) s_.stats.cells = s_.state.drawn().mesh->tets.size();
    s_.stats.resolution_level = scale_.level();
    s_.stats.moving = scale_.moving();
    s_.stats.target_ms = scale_.target_ms();
    window_extent_ = extent;
    extent = scale_.extent(extent);
    frame::FrameRenderer& drawing = active();
    drawing.resize(extent);
    try {
      s_.stats.prepared(drawing.prepare(s_.camera.camera(), s_.state.settings));
      s_.last_good = s_.state.settings;
    } catch (const InputError& e) {  // a setting this data or device refuses: say so, keep the last good one
      s_.message(e.what());
      s_.state.settings = s_.last_good;
      s_.stats.prepared(drawing.prepare(s_.camera.camera(), s_.state.settings));
    }
    compare_.update(s_);
    s_.renderer.resize(extent);  // the difference view's GPU frame may have left the reference's size
  }
  void record(VkCommandBuffer cmd, vk::GpuTimer& timer, VkImage target, VkExtent2D extent) override {
    in_flight_level_ = scale_.level();
    drawn_moving_ = scale_.moving();
    recorded_at_ = std::chrono::steady_clock::now();
    frame::FrameRenderer& drawing = active();
    drawing.record(cmd, s_.camera.camera(), s_.state.settings, timer);
    compare_.record(cmd, s_);
    vk::ScopedPass pass(timer, cmd, "present-blit");
    compare_.present(cmd, s_, drawing.display(), target, extent);
  }
  std::optional<std::string> take_capture() override { return std::exchange(s_.capture_path, std::nullopt); }
  void capture_failed(const std::string& message) override { s_.failed("Could not write", message); }
  void stopping() override {
    if (s_.loading.job) {  // closed mid-load: stop it and wait (promptly: the io layer checks often)
      const auto stop = std::chrono::steady_clock::now();
      s_.loading.job->cancel();
      s_.loading.job.reset();
      ++s_.report.loads_cancelled;
      s_.report.seconds_to_stop_load = std::chrono::duration<double>(std::chrono::steady_clock::now() - stop).count();
    }
  }
  // Work made on the present thread while the loop goes on reading input: the first frame's
  // pipelines, and, once the window falls behind at full resolution, the coarse proxies (a
  // proxy's cells, their upload and its pipelines: about 190 ms on lavapipe for the compute
  // backend, which would otherwise hold the loop in the middle of a drag).
  std::function<void()> setup_work() override {
    if (!warmed_up_) {
      warmed_up_ = true;
      return [this, camera = s_.camera.camera(), settings = s_.state.settings, extent = s_.swapchain.extent()] {
        try {
          s_.renderer.resize(extent);
          s_.renderer.prepare(camera, settings);
        } catch (const InputError&) {  // the first frame's prepare_frame says what was refused
        }
      };
    }
    const std::shared_ptr<const TetMesh> mesh = s_.state.drawn().mesh;
    if (scale_.level() == 0 || !proxy_allowed() || (proxies_[0].of == mesh && proxies_[1].of == mesh)) return {};
    return [this, mesh, camera = s_.camera.camera(), settings = s_.state.settings, extent = InteractiveScale::proxy_extent(window_extent_)] {
      for (uint32_t i = 0; i < proxies_.size(); ++i) {
        if (build_proxy(i, mesh)) ++s_.report.proxies_made_beside_frames;
        try {  // its pipelines and buffers made now, not on its first frame
          proxies_[i].renderer->resize(extent);
          proxies_[i].renderer->prepare(camera, settings);
        } catch (const InputError&) {  // a setting the proxy refuses: its frame will say so
        }
      }
    };
  }
  uint32_t& frame_index() override { return s_.frame_index; }
  const std::vector<std::string>& inputs() const override { return s_.inputs; }

 private:
  ViewerSession& s_;
  CompareView& compare_;
  const std::vector<ScriptCommand>& script_;
  uint32_t max_tetlet_;
  size_t next_command_ = 0;
  // What draws this frame: the data's renderer, or a coarse proxy's while the camera moves.
  frame::FrameRenderer& active() {
    if (!scale_.proxy()) return s_.renderer;
    Proxy& p = proxies_[scale_.proxy_index()];
    return p.renderer ? *p.renderer : s_.renderer;
  }
  // Past 1/8 of the window, fewer cells: a coarse proxy of the data (not for marching, whose
  // field the proxy does not carry, nor for data already about as coarse).
  bool proxy_allowed() const {
    const volume::ResolveSettings& resolve = s_.state.settings.resolve;
    return !resolve.march.enabled && resolve.quantity != volume::Quantity::Isosurface && s_.state.drawn().mesh &&
           s_.state.drawn().mesh->tets.size() > 4 * kProxyCells;
  }
  // The proxy of `mesh` at proxy level `index`, made the first time it is needed (setup_work,
  // else the frame that needs it) and again when the data changes. Whether it was made now.
  bool build_proxy(uint32_t index, const std::shared_ptr<const TetMesh>& mesh) {
    Proxy& p = proxies_[index];
    if (p.renderer && p.of == mesh) return false;
    s_.device.wait_idle();
    p.renderer.reset();
    p.mesh = std::make_unique<TetMesh>(coarse_proxy(*mesh, kProxyCubes[index]));
    p.renderer.emplace(s_.device, *p.mesh);
    p.of = mesh;
    return true;
  }
  // 16^3 cubes (24,576 cells): lavapipe draws the default dataset, such a grid, in 60-80 ms at
  // 160x100 (docs/results.md, "lavapipe (this machine)"); 10^3 (6,000 cells) where that is still
  // too slow (the mesh backend's frame there).
  static constexpr uint32_t kProxyCubes[2] = {16, 10};
  static constexpr size_t kProxyCells = 6 * 16 * 16 * 16;
  struct Proxy {
    std::unique_ptr<TetMesh> mesh;
    std::optional<frame::FrameRenderer> renderer;
    std::shared_ptr<const TetMesh> of;
  };

  InteractiveScale scale_;
  std::array<Proxy, 2> proxies_;
  Camera last_camera_;
  bool have_camera_ = false;
  uint32_t in_flight_level_ = 0, finished_level_ = 0;
  std::chrono::steady_clock::time_point recorded_at_;
  VkExtent2D window_extent_{1, 1};  // the window's size at the last frame
  double finished_ms_ = 0.0;  // GPU time of the last finished frame, not yet given to scale_
  bool drawn_moving_ = false, after_motion_ = false;  // the frame in flight moved; one moved before
  bool pointer_held_ = false;  // a mouse button is held on the view (window_loop)
  bool warmed_up_ = false;     // the first frame was prepared by setup_work
};

}  // namespace

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wl && *wl);
}

ViewerReport run_viewer(const TetMesh& mesh, const ViewerOptions& options) {
  ViewState state;
  state.datasets.push_back(make_dataset(mesh, options.settings.resolve.march.enabled
                                                  ? std::optional<volume::AnalyticField>(options.settings.resolve.march.field)
                                                  : std::nullopt));
  return run_viewer(std::move(state), options);
}

ViewerReport run_viewer(ViewState state, const ViewerOptions& options) {
  const TerminateSignals signals;

  state.settings = options.settings;
  if (options.mode.empty()) {  // the mode of the table that draws these settings
    const frame::VolumeMode* mode = frame::find_volume_mode(options.settings.ordering, options.settings.resolve.march.enabled);
    if (!mode)
      throw InputError("mode", std::string("no volume mode marches in ") + frame::ordering_name(options.settings.ordering) + ": name one");
    state.mode = mode->name;
  } else {
    state.mode = options.mode;
  }
  state.show_ui = options.show_ui;
  state.tf_preset = options.settings.resolve.transfer.name;
  rebuild_scene(state);

  PresentingDevice presenting(options.validation, options.device_index);
  const vk::Instance& instance = presenting.instance;
  const vk::DeviceCapabilities& caps = presenting.caps;
  vk::Device& device = presenting.device;
  frame::FrameSettings settings = options.settings;
  if (options.backend_auto) resolve_auto_backend(settings, device);
  state.settings.backend = settings.backend;
  state.settings.backend_reason = settings.backend_reason;

  Window window(options.width, options.height, "Prismoid");
  Surface surface(instance.get(), window.get());
  vk::Swapchain swapchain(device, surface.get(), window.framebuffer_extent());
  // Held in place so a new scene can replace it (sync_renderer) under the same references.
  std::optional<frame::FrameRenderer> renderer_slot;
  renderer_slot.emplace(device, *state.drawn().mesh);
  frame::FrameRenderer& renderer = *renderer_slot;
  ImGuiLayer ui(device, window.get(), swapchain);
  SwapchainCapture capture(device);

  ViewerReport report;
  report.device_name = caps.name;
  const Bounds bounds = state.drawn().bounds;
  ViewerSession s{std::move(state), settings, window, device, swapchain, renderer,
                  options.camera ? CameraController(bounds, *options.camera) : CameraController(bounds), {}, {}, report};
  CompareView compare(device);
  s.stats.frame.device = caps.name;
  s.stats.cells = s.state.drawn().mesh->tets.size();
  s.loading.defaults = options.open_defaults;
  s.loading.recent_file = options.recent_file;
  s.loading.renderer_slot = &renderer_slot;
  s.loading.drawn_mesh = s.state.drawn().mesh;
  report.mesh_uploads = 1;  // renderer_slot's
  s.inputs = options.inputs;
  const uint32_t max_tetlet = volume::max_tetlet_size(device);

  VolumeWindow content(s, compare, options.script, max_tetlet, options.moving_target_ms);
  WindowParts parts{window, device, swapchain, ui, capture};
  run_window_loop(parts, content, options, report);

  report.last_frame = s.stats;
  report.camera = s.camera.camera();
  report.mode = s.state.mode;
  report.quantity = s.state.settings.resolve.quantity;
  report.compare = compare.status().last;
  report.compare_reference_seconds = compare.status().reference_seconds;
  report.compare_passes = compare.status().b_passes;
  report.validation_messages = instance.validation_log().count();
  report.datasets = s.state.datasets.size();
  report.datasets_visible = size_t(std::count_if(s.state.datasets.begin(), s.state.datasets.end(), [](const Dataset& d) { return d.visible; }));
  return report;
}

}  // namespace prismoid::app
