#pragma once
// The one frame loop of every window (the volume window, viewer.cpp, and the surface window,
// surface_viewer.cpp): script commands due, input, minimized windows, resizes, the fence of the
// frame in flight, the UI, the content's frame, the UI over it, a screenshot, submission and
// presentation. Submission and presentation run on a thread of their own (present_thread.hpp):
// until the frame has been drawn, the loop only reads the mouse into the camera, every few
// milliseconds, so that no frame, however slow, holds up the input. SIGTERM and SIGINT end it
// as closing the window does. What differs between the
// windows is their content (WindowContent): what they draw and what their keys and panels do.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "app/viewer/camera_controller.hpp"
#include "app/viewer/imgui_layer.hpp"
#include "app/viewer/screenshot.hpp"
#include "app/viewer/viewer.hpp"
#include "app/viewer/window.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/swapchain.hpp"
#include "renderer/vk/timer.hpp"

namespace prismoid::app {

// SIGTERM and SIGINT, while one of these lives, ask the window loop to end (the process then
// exits as when the window is closed) instead of ending the process. Made before the window's
// set-up, so a signal during it is not lost either; the previous handlers come back after.
class TerminateSignals {
 public:
  TerminateSignals();
  ~TerminateSignals();
  TerminateSignals(const TerminateSignals&) = delete;
  TerminateSignals& operator=(const TerminateSignals&) = delete;
  // Whether a signal arrived since this object was made.
  static bool requested();

 private:
  void (*previous_term_)(int);
  void (*previous_int_)(int);
};

// What a window shows and how it answers, for run_window_loop.
class WindowContent {
 public:
  virtual ~WindowContent() = default;
  virtual CameraController& camera() = 0;
  virtual bool show_ui() const = 0;
  // Before each frame's input: runs what is due (script commands, finished loads).
  virtual void run_due() = 0;
  // Events polled: the CPU time since the last frame started.
  virtual void frame_started(double cpu_frame_ms) = 0;
  virtual void on_key(const KeyPress& key) = 0;
  virtual void on_drop(const std::vector<std::string>& paths) { (void)paths; }
  // After the mouse was handled: whether a drag on the view is in progress (a button held,
  // the mouse moving or paused; a drag begun on a panel does not count).
  virtual void pointer_held(bool held) { (void)held; }
  // The frame in flight has completed: its GPU passes (the content's, present-blit, ui). `last`:
  // after the loop ended (the content reads its own counters only while the loop runs).
  virtual void frame_finished(std::vector<vk::PassTiming> passes, bool last) = 0;
  // The window title and stdout line of --print-timings ("Prismoid - ..." with the pass times).
  virtual std::string timings_line() const = 0;
  // Panels and overlays, between the UI layer's begin_frame and finish_frame.
  virtual void draw_ui() = 0;
  // After the UI, before the swapchain image is acquired: settings applied, the frame planned.
  virtual void prepare_frame(VkExtent2D extent) = 0;
  // Records the content's passes and the "present-blit" of its image into `target`.
  virtual void record(VkCommandBuffer cmd, vk::GpuTimer& timer, VkImage target, VkExtent2D extent) = 0;
  // A screenshot the next recorded frame takes (taken: asked once).
  virtual std::optional<std::string> take_capture() = 0;
  // A screenshot that could not be written.
  virtual void capture_failed(const std::string& message) = 0;
  // The loop ended (closed, SIGTERM/SIGINT, --frames), before the device is waited for.
  virtual void stopping() {}
  // Slow set-up the content wants before its next frame (a coarse proxy's cells, upload and
  // pipelines): run on the present thread, like a frame, while the loop reads input; it may use
  // the queue. Empty: none.
  virtual std::function<void()> setup_work() { return {}; }
  // The frame counter the loop advances (scripts and --frames count in it).
  virtual uint32_t& frame_index() = 0;
  virtual const std::vector<std::string>& inputs() const = 0;  // files a screenshot may not replace
};

// What the window's set-up made, for the loop.
struct WindowParts {
  Window& window;
  const vk::Device& device;
  vk::Swapchain& swapchain;
  ImGuiLayer& ui;
  SwapchainCapture& capture;
};

// Runs frames until the window is closed, a TerminateSignals saw SIGTERM or SIGINT, or
// options.max_frames have run; the device is idle when it returns. Counts presented frames,
// minimized frames and swapchain recreations in `report`.
void run_window_loop(WindowParts& parts, WindowContent& content, const ViewerOptions& options, ViewerReport& report);

}  // namespace prismoid::app
