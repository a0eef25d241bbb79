#include "app/viewer/viewer.hpp"

#include <imgui.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "app/viewer/dataset_list.hpp"
#include "app/viewer/compare_panel.hpp"
#include "app/viewer/compare_view.hpp"
#include "app/viewer/window_input.hpp"
#include "app/viewer/viewer_session.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/memory.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

std::atomic<bool> g_terminate{false};
extern "C" void on_terminate_signal(int) { g_terminate = true; }

// The frame's passes (A's, and B's in split view), the view into swapchain image `index`, the
// UI over it, a screenshot.
void record_frame(VkCommandBuffer cmd, ViewerSession& s, CompareView& compare, ImGuiLayer& ui, SwapchainCapture& capture,
                  vk::GpuTimer& timer, uint32_t index) {
  vk::check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  vk::check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  timer.reset(cmd);
  s.renderer.record(cmd, s.camera.camera(), s.state.settings, timer);
  compare.record(cmd, s);
  {
    vk::ScopedPass pass(timer, cmd, "present-blit");
    compare.present(cmd, s, s.renderer.display(), s.swapchain.image(index), s.swapchain.extent());
  }
  {
    vk::ScopedPass pass(timer, cmd, "ui");
    ui.record(cmd, index, s.state.show_ui);
  }
  if (s.capture_path)
    capture.record(cmd, s.swapchain.image(index), s.swapchain.extent(), s.swapchain.format(), *std::exchange(s.capture_path, std::nullopt));
  vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
}

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

void print_timings(GLFWwindow* window, const FrameStats& stats) {
  std::ostringstream title;
  title << "Prismoid - " << stats.device_name << " -";
  for (const auto& t : stats.gpu_passes) title << " " << t.name << " " << t.gpu_ms << " ms";
  glfwSetWindowTitle(window, title.str().c_str());
  std::printf("%s\n", title.str().c_str());
  std::fflush(stdout);
}

}  // namespace

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wl && *wl);
}

std::string mode_of(const frame::FrameSettings& settings) {
  const bool march = settings.resolve.march.enabled;
  switch (settings.ordering) {
    case frame::Ordering::MeshOrder: return march ? "interval-march" : "interval";
    case frame::Ordering::GpuSort: return march ? "interval-march" : "interval-sorted";
    case frame::Ordering::Exact: return march ? "interval-march-exact-order" : "interval-exact-order";
  }
  return "interval";
}

ViewerReport run_viewer(const TetMesh& mesh, const ViewerOptions& options) {
  ViewState state;
  state.datasets.push_back(make_dataset(mesh, options.settings.resolve.march.enabled
                                                  ? std::optional<volume::AnalyticField>(options.settings.resolve.march.field)
                                                  : std::nullopt));
  return run_viewer(std::move(state), options);
}

ViewerReport run_viewer(ViewState state, const ViewerOptions& options) {
  g_terminate = false;
  auto previous_term = std::signal(SIGTERM, on_terminate_signal);
  auto previous_int = std::signal(SIGINT, on_terminate_signal);
  struct RestoreSignals {
    decltype(previous_term) term, intr;
    ~RestoreSignals() { std::signal(SIGTERM, term); std::signal(SIGINT, intr); }
  } restore{previous_term, previous_int};

  state.settings = options.settings;
  state.mode = options.mode.empty() ? mode_of(options.settings) : options.mode;
  state.show_ui = options.show_ui;
  state.tf_preset = options.settings.resolve.transfer.name;
  rebuild_scene(state);

  PresentingDevice presenting(options.validation, options.device_index);
  const vk::Instance& instance = presenting.instance;
  const vk::DeviceCapabilities& caps = presenting.caps;
  vk::Device& device = presenting.device;

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
  ViewerSession s{std::move(state), options.settings, window, device, swapchain, renderer,
                  options.camera ? CameraController(bounds, *options.camera) : CameraController(bounds), {}, {}, report};
  CompareView compare(device);
  s.stats.device_name = caps.name;
  s.stats.cells = s.state.drawn().mesh->tets.size();
  s.loading.defaults = options.open_defaults;
  s.loading.recent_file = options.recent_file;
  s.loading.renderer_slot = &renderer_slot;
  s.loading.drawn_mesh = s.state.drawn().mesh;
  s.inputs = options.inputs;
  const uint32_t max_tetlet = volume::max_tetlet_size(device);

  vk::GpuTimer timer(device, 16);
  FrameResources frame_resources(device);
  const VkSemaphore image_available = frame_resources.image_available.get();
  const vk::UniqueFence& in_flight = frame_resources.in_flight;
  const VkCommandBuffer cmd = frame_resources.cmd;

  auto recreate = [&] { recreate_swapchain(swapchain, window, ui, report); };
  auto finish_frame_capture = [&] { finish_capture(capture, report, s.inputs, [&](const std::string& m) { s.failed("Could not write", m); }); };

  bool frame_in_flight = false;
  MouseState mouse;
  glfwGetCursorPos(window.get(), &mouse.last.x, &mouse.last.y);
  auto last_frame = std::chrono::steady_clock::now();
  auto last_print = last_frame;
  size_t next_command = 0;

  while (!glfwWindowShouldClose(window.get()) && !g_terminate) {
    poll_loads(s);
    run_script(s, compare, options.script, next_command);
    ++s.frame_index;
    if (options.max_frames && s.frame_index > options.max_frames) break;
    glfwPollEvents();
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::min(std::chrono::duration<double>(now - last_frame).count(), 0.1);
    s.stats.cpu_frame_ms = std::chrono::duration<double, std::milli>(now - last_frame).count();
    last_frame = now;
    handle_mouse(s.window, s.camera, mouse, s.swapchain.extent(), s.state.show_ui && ui.wants_mouse(),
                 ImGui::GetIO().WantCaptureKeyboard, seconds);
    for (const KeyPress& key : window.take_keys())
      if (!(s.state.show_ui && ui.wants_keyboard())) s.on_key(key);
    for (const auto& dropped : window.take_drops()) open_datasets(s, dropped, s.panel.data.array);

    const VkExtent2D fb = window.framebuffer_extent();
    if (fb.width == 0 || fb.height == 0 || glfwGetWindowAttrib(window.get(), GLFW_ICONIFIED)) {
      ++report.frames_skipped_minimized;
      glfwWaitEventsTimeout(0.05);
      continue;
    }
    if (fb.width != swapchain.extent().width || fb.height != swapchain.extent().height) recreate();

    vk::check(vkWaitForFences(device.get(), 1, in_flight.ptr(), VK_TRUE, UINT64_MAX), "vkWaitForFences");
    if (frame_in_flight) {  // the last frame finished: its numbers and its screenshot
      s.stats.gpu_passes = timer.read();
      if (renderer.interval_pass().counts_draws()) {
        const auto counts = renderer.interval_pass().read_counts();
        s.stats.counted = true;
        s.stats.fragments = counts.fragments;
        s.stats.primitives = counts.primitives;
      }
      compare.frame_finished();
      finish_frame_capture();
      frame_in_flight = false;
      if (options.print_timings && now - last_print > std::chrono::seconds(1)) {
        print_timings(window.get(), s.stats);
        last_print = now;
      }
    }

    ui.begin_frame();
    if (s.state.show_ui) {
      const UiRequests requests = draw_side_panel(s.state, s.panel, s.stats, s.camera, max_tetlet);
      draw_hud(s.stats, s.state);
      draw_compare_overlay(compare.status(), s.state, s.stats);
      s.apply(requests);
    }
    ui.finish_frame();

    sync_renderer(s);
    renderer.resize(swapchain.extent());
    try {
      s.stats.report = renderer.prepare(s.camera.camera(), s.state.settings);
      s.last_good = s.state.settings;
    } catch (const InputError& e) {  // a setting this data or device refuses: say so, keep the last good one
      s.message(e.what());
      s.state.settings = s.last_good;
      s.stats.report = renderer.prepare(s.camera.camera(), s.state.settings);
    }
    compare.update(s);
    renderer.resize(swapchain.extent());  // the difference view's GPU frame may have left the reference's size

    const auto index = swapchain.acquire(image_available);
    if (!index) {
      recreate();
      continue;
    }
    vk::check(vkResetFences(device.get(), 1, in_flight.ptr()), "vkResetFences");
    record_frame(cmd, s, compare, ui, capture, timer, *index);
    submit_frame(device, cmd, image_available, swapchain.render_finished(*index), in_flight.get());
    frame_in_flight = true;
    if (!swapchain.present(*index, swapchain.render_finished(*index))) recreate();
    ++report.frames_presented;
  }
  if (s.loading.job) {  // closed mid-load: stop it and wait (promptly: the io layer checks often)
    const auto stop = std::chrono::steady_clock::now();
    s.loading.job->cancel();
    s.loading.job.reset();
    ++report.loads_cancelled;
    report.seconds_to_stop_load = std::chrono::duration<double>(std::chrono::steady_clock::now() - stop).count();
  }
  device.wait_idle();
  if (frame_in_flight) {
    s.stats.gpu_passes = timer.read();
    compare.frame_finished();
    finish_frame_capture();
  }
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
