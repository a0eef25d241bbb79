#pragma once
// The window: GLFW + a Vulkan swapchain over the same FrameRenderer the offscreen path uses.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "renderer/frame/frame_renderer.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::app {

// A scripted action at a given frame, so tests can drive the window without a person.
struct ViewerAction {
  enum class Kind { Resize, Iconify, Restore, Close } kind;
  uint32_t frame = 0;
  uint32_t width = 0, height = 0;  // Resize only
};

struct ViewerOptions {
  uint32_t width = 1280, height = 800;
  bool validation = false;
  std::optional<uint32_t> device_index;
  std::optional<Camera> camera;           // fitted to the data when absent
  frame::FrameSettings settings;          // what to show and how (quantity, ordering, transfer function...)
  uint32_t max_frames = 0;                // 0: until the window is closed or SIGTERM
  std::vector<ViewerAction> script;
  bool print_timings = true;              // GPU times in the title bar and once a second on stdout
};

struct ViewerReport {
  uint32_t frames_presented = 0;
  uint32_t swapchain_recreations = 0;
  uint32_t frames_skipped_minimized = 0;
  size_t validation_messages = 0;
  std::string device_name;
};

// Opens the window on `mesh` and runs until closed. Throws vk::NoSuitableDevice when no
// device can present, std::runtime_error when no display can be opened.
ViewerReport run_viewer(const TetMesh& mesh, const ViewerOptions& options);

// Whether a display server looks reachable (DISPLAY or WAYLAND_DISPLAY set).
bool display_available();

}  // namespace prismoid::app
