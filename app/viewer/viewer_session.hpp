#pragma once
// Internal to the viewer: everything one window session holds, and the actions that keys,
// panels and script commands share (viewer.cpp runs the frame loop, viewer_actions.cpp the
// actions).
#include <chrono>
#include <optional>
#include <string>

#include "app/viewer/camera_controller.hpp"
#include "app/viewer/imgui_layer.hpp"
#include "app/viewer/panels.hpp"
#include "app/viewer/screenshot.hpp"
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
  // A script's clock: frames counted while no wait-reference holds the script.
  uint32_t script_frame = 0;
  // A script's wait-reference: its commands pause until the difference view settles or then.
  std::optional<std::chrono::steady_clock::time_point> reference_deadline;

  double aspect() const;
  void message(const std::string& text);  // shown in the panel, kept in the report, on stderr
  void on_key(const KeyPress& key);
  void run(const ScriptCommand& command);
  void apply(const UiRequests& requests);
  void copy_camera();
  void render_at(uint32_t width, uint32_t height, const std::string& path);
};

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
