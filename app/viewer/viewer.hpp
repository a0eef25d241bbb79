#pragma once
// The window: GLFW + a Vulkan swapchain over the same FrameRenderer the offscreen path uses,
// Dear ImGui panels over it, a ParaView-like camera, and a script option that drives all of it
// without a person (tests, benchmarks).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/common/dataset_loader.hpp"
#include "app/viewer/panels.hpp"
#include "app/viewer/reference_job.hpp"
#include "app/viewer/view_state.hpp"
#include "app/viewer/viewer_script.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::app {

struct ViewerOptions {
  uint32_t width = 1280, height = 800;
  bool validation = false;
  std::optional<uint32_t> device_index;
  std::optional<Camera> camera;   // fitted to the data when absent
  frame::FrameSettings settings;  // what to show and how (quantity, ordering, transfer function...)
  std::string mode;               // the CLI's --mode name; empty: the table's mode of settings' ordering and march
  bool backend_auto = false;      // --volume-backend auto: the backend is measured on the window's device
  uint32_t max_frames = 0;        // 0: until the window is closed or SIGTERM
  std::vector<ScriptCommand> script;
  bool print_timings = true;      // GPU times in the title bar and once a second on stdout
  bool show_ui = true;
  // While the camera moves, frames are drawn coarser to hold this frame time (app/viewer/interactive_scale.hpp).
  double moving_target_ms = 100.0;
  LoadRequest open_defaults;          // how files opened in the window are read (density scale, role)
  std::filesystem::path recent_file;  // the recent-files list (recent_files_path()); empty: none kept
  // The files read to start the window (datasets, --tf, --script): the window's screenshots,
  // renders and exports may not replace them, nor any file it opens later.
  std::vector<std::string> inputs;
};

// One dataset the window tried to open.
struct LoadRecord {
  std::string path;
  bool loaded = false;
  bool cancelled = false;
  std::string error;             // the data layer's message when it did not load
  uint32_t frames_presented = 0;  // while it loaded: the window kept drawing
  double seconds = 0.0;
  uint64_t cells = 0;
};

struct ViewerReport {
  uint32_t frames_presented = 0;
  uint32_t swapchain_recreations = 0;
  uint32_t frames_skipped_minimized = 0;
  size_t validation_messages = 0;
  std::string device_name;
  FrameStats last_frame;                 // the HUD's numbers for the last finished frame
  Camera camera;                         // at the end
  std::string mode;                      // at the end
  uint32_t msa_amortization = 0;         // surface window: msa shades every n-th frame (0: every frame), at the end
  std::string msa_charts = "projection";  // surface window: msa's meshlet charts at the end (msa::parametrization_name)
  std::string compare_mode;               // surface window: the split view's right mode at the end ("" when off)
  volume::Quantity quantity{};           // at the end
  std::vector<std::string> files_written;  // screenshots and renders, in order
  std::vector<std::string> camera_lines;   // printed by C / print-camera
  std::vector<std::string> messages;       // refused commands and settings, errors
  std::vector<std::string> error_popups;   // "TITLE: TEXT" of each error popup opened (failed loads and requests)
  std::vector<std::pair<uint32_t, uint64_t>> resident_kib;  // (frame, resident memory) at each `rss`
  std::vector<LoadRecord> loads;           // opened in the window, in the order they ended
  std::vector<uint32_t> steps_shown;       // time steps shown after the first, in order
  // The volume renderer's uploads: whole meshes (the first scene, and every scene of other points
  // or cells), and fields alone (a time step of the mesh drawn).
  uint32_t mesh_uploads = 0, field_uploads = 0;
  size_t datasets = 0;                     // in the scene at the end
  size_t datasets_visible = 0;
  std::string last_load_error;
  uint32_t loads_cancelled = 0;            // by Cancel, cancel-load or closing the window
  double seconds_to_stop_load = 0.0;       // closed mid-load: from the close to the load's thread ending
  // The difference view's last comparison (statistics, size and channels; no heat map), and
  // how long its CPU reference took.
  std::optional<FrameComparison> compare;
  std::vector<FrameComparison> comparisons;  // every comparison the difference view showed, in order
  double compare_reference_seconds = 0.0;
  std::vector<vk::PassTiming> compare_passes;  // split view: B's passes in the last finished frame
  // Volume window: each frame drawn while the camera moved, as (wall ms from its recording to
  // its end, its resolution level: 1/2^level per side), and the wall ms of the frames drawn with
  // a still camera (full resolution) after the first motion.
  std::vector<std::pair<double, uint32_t>> moving_frames;
  std::vector<double> still_frames_ms;
  // Volume window: coarse proxies made on the present thread while the loop read input, and
  // made by the frame that needed them (the loop held meanwhile).
  uint32_t proxies_made_beside_frames = 0, proxies_made_in_frames = 0;
  // Every window: the longest wait between two readings of the input (the loop reads it every
  // few milliseconds while a frame is drawn, and once before each frame's UI and recording),
  // and how many readings fell while a frame was being drawn.
  double longest_input_gap_ms = 0.0;
  uint64_t input_reads_while_drawing = 0;
};

// Opens the window on the state's visible datasets and runs until closed (a load still running
// is cancelled and waited for). Throws
// vk::NoSuitableDevice when no device can present, std::runtime_error when no display can be
// opened, InputError for a bad initial setting.
ViewerReport run_viewer(ViewState state, const ViewerOptions& options);
ViewerReport run_viewer(const TetMesh& mesh, const ViewerOptions& options);

// Whether a display server looks reachable (DISPLAY or WAYLAND_DISPLAY set).
bool display_available();

}  // namespace prismoid::app
