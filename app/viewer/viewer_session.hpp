#pragma once
// Internal to the viewer: everything one window session holds, and the actions that keys,
// panels and script commands share (viewer.cpp runs the frame loop, viewer_actions.cpp the
// actions).
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/camera_controller.hpp"
#include "app/viewer/imgui_layer.hpp"
#include "app/viewer/panels.hpp"
#include "app/viewer/screenshot.hpp"
#include "app/viewer/time_steps.hpp"
#include "app/viewer/view_state.hpp"
#include "app/viewer/viewer.hpp"
#include "app/viewer/viewer_loading.hpp"
#include "app/viewer/window.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/swapchain.hpp"

namespace prismoid::app {

struct ViewerSession {
  ViewState state;
  frame::FrameSettings last_good;  // the settings of the last frame prepare() accepted
  Window& window;
  const vk::Device& device;
  vk::Swapchain& swapchain;
  frame::FrameRenderer& renderer;
  CameraController camera;
  PanelState panel;
  FrameStats stats;
  ViewerReport& report;
  uint32_t frame_index = 0;
  std::optional<std::string> capture_path;  // a screenshot the next recorded frame takes
  uint32_t screenshot_count = 0;
  LoadingState loading;  // datasets opening in the background (viewer_loading.cpp)
  TimeStepping time;     // the active dataset's time steps (time_steps.cpp)
  // A script's clock: frames counted while no wait-reference holds the script.
  uint32_t script_frame = 0;
  // A script's wait-reference: its commands pause until the difference view settles or then.
  std::optional<std::chrono::steady_clock::time_point> reference_deadline;
  // The files the window read (datasets, the script, colour maps): its outputs may not be any
  // of them (app/common/output_files.hpp).
  std::vector<std::string> inputs;

  double aspect() const;
  void message(const std::string& text);  // shown in the panel, kept in the report, on stderr
  // A request that failed (a file not read or written, a size refused): the message, and the
  // error popup titled `title`.
  void failed(const std::string& title, const std::string& text);
  // Runs `action`; an exception from it becomes failed(title, where: what) and the window goes on.
  void attempt(const std::string& title, const std::string& where, const std::function<void()>& action);
  void on_key(const KeyPress& key);
  void run(const ScriptCommand& command);
  void apply(const UiRequests& requests);
  void copy_camera();
  void render_at(uint32_t width, uint32_t height, const std::string& path);
  void request_screenshot(const std::string& path);  // checked now, written when the frame finishes
  void import_transfer_function(const std::string& path);  // keeps the range and density scale
  void export_transfer_function(const std::string& path);
};

// The sizes the window accepts for `render W H FILE` and `resize W H`: render's --size bounds
// (1 to 16384 pixels a side); InputError naming the command otherwise.
void check_render_size(uint32_t width, uint32_t height);
void resize_window(Window& window, uint32_t width, uint32_t height);

// The key a script names: a letter, digit or Escape, optionally after "shift+".
KeyPress key_from_name(const std::string& name);
// A script argument that is on or off (InputError naming the line otherwise).
bool script_on_off(const ScriptCommand& c, size_t index = 0);

// What every window does with the camera, shared by the volume and surface windows: the keys
// R (fit), F (fly), X/Y/Z (shift: negative) and the script's camera verbs (camera, view,
// reset, rotate, pan, zoom, drag, fly, fly-move, fly-look). false when the key or verb is not
// a camera one.
bool camera_key(CameraController& camera, const KeyPress& key, double aspect);
bool run_camera_command(CameraController& camera, const ScriptCommand& c, VkExtent2D extent, const Bounds& bounds);

}  // namespace prismoid::app
