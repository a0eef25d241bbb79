#pragma once
// The window's panels, drawn with Dear ImGui each frame: the view (camera) panel, the mode
// panel with the frame plan, the transfer-function editor, and the HUD. They edit the
// ViewState directly; what needs the frame loop (camera moves, screenshots, renders) they ask
// for through UiRequests, which the loop carries out exactly as it does for keys and scripts.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/camera_controller.hpp"
#include "app/viewer/open_panel.hpp"
#include "app/viewer/view_state.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/mixed/frame_stats.hpp"
#include "renderer/vk/timer.hpp"

namespace prismoid::app {

// What the HUD and the frame plan show about the last frame that finished: its typed stats, the
// struct `render` reports a frame from (renderer/mixed/frame_stats.hpp: the device, the GPU passes,
// the volume's report with its plan, CPU passes, ordering and draw counts), and what only the
// window knows.
struct FrameStats {
  mixed::FrameStats frame = [] {
    mixed::FrameStats f;
    f.gpu = true;
    f.volume.emplace();
    return f;
  }();
  const frame::FrameReport& report() const { return frame.volume->report; }
  frame::FrameReport& report() { return frame.volume->report; }
  // The report prepare() gave the next frame, keeping the draw counts of the last finished one.
  void prepared(frame::FrameReport next) {
    const frame::FrameReport& last = report();
    next.counted = last.counted;
    next.fragments = last.fragments;
    next.primitives = last.primitives;
    report() = std::move(next);
  }
  double cpu_frame_ms = 0.0;               // wall time between the last two frames
  uint64_t cells = 0;                      // cells drawn (every cell of the dataset)
  // The volume's resolution this frame: 1/2^resolution_level of the window per side, coarser
  // only while the camera moves (moving), to hold target_ms (app/viewer/interactive_scale.hpp).
  uint32_t resolution_level = 0;
  bool moving = false;
  double target_ms = 0.0;
};

struct RenderRequest {
  uint32_t width = 1920, height = 1080;
  std::string path;
};

struct UiRequests {
  std::optional<AxisView> axis_view;
  bool reset_camera = false;
  bool toggle_fly = false;
  bool copy_camera = false;
  std::optional<std::string> apply_camera_line;
  std::optional<std::string> screenshot;  // path
  std::optional<RenderRequest> render;
  std::optional<std::string> import_tf, export_tf;  // ParaView colour-map paths
  DataRequests data;  // open, cancel, show, active
};

// Text the panels keep between frames (text boxes, messages, the dragged point).
struct PanelState {
  char camera_text[512] = "";
  char screenshot_path[256] = "prismoid-screenshot.png";
  char render_path[256] = "prismoid-render.png";
  int render_size[2] = {1920, 1080};
  char tf_path[256] = "colormap.json";
  int dragged_point = -1;
  std::string message;  // the last error or confirmation, shown under the panels
  DataPanel data;       // the Data section: path box, recent files, load progress
};

// The left-hand panel: data, view, mode and transfer function; returns the requests it made.
UiRequests draw_side_panel(ViewState& state, PanelState& panel, const FrameStats& stats, const CameraController& camera,
                           uint32_t max_tetlet_size);
void draw_view_section(PanelState& panel, const CameraController& camera, UiRequests& requests);
void draw_mode_section(ViewState& state, PanelState& panel, uint32_t max_tetlet_size);
// The passes of the last frame, their times and why each runs.
void draw_frame_plan(const ViewState& state, const FrameStats& stats);
void draw_tf_section(ViewState& state, PanelState& panel, UiRequests& requests);
// The HUD in the top-right corner.
void draw_hud(const FrameStats& stats, const ViewState& state);

// Why a pass of the frame runs: the frame plan's reason (the window's own passes: theirs).
std::string pass_reason(const std::string& pass, const frame::FramePlan& plan);

}  // namespace prismoid::app
