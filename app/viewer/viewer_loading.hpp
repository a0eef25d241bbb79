#pragma once
// Internal to the viewer: opening datasets while the window runs. Paths from the path box, the
// recent list, drops and scripts queue here; one DatasetLoad runs at a time on its own thread;
// the frame loop polls it, adds what loaded to the scene, and rebuilds the renderer (on the
// thread that owns the device) when the drawn scene changed.
#include <chrono>
#include <deque>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/common/dataset_loader.hpp"
#include "app/viewer/load_job.hpp"
#include "app/viewer/open_panel.hpp"
#include "renderer/frame/frame_renderer.hpp"

namespace prismoid::app {

struct ViewerSession;

struct LoadingState {
  LoadRequest defaults;                  // options of opened files (density scale, role), from the command line
  std::deque<LoadRequest> queue;         // waiting behind the running job
  std::unique_ptr<DatasetLoad> job;
  uint32_t frames_at_start = 0;          // frames presented when the job started
  std::filesystem::path recent_file;     // empty: no recent list kept
  std::vector<std::string> recent;
  bool recent_read = false;
  bool fit_camera = false;               // fit the camera to the next scene (a dataset was added)
  // The renderer's storage and the mesh it draws: a new scene replaces the renderer in place.
  std::optional<frame::FrameRenderer>* renderer_slot = nullptr;
  std::shared_ptr<const TetMesh> drawn_mesh;
  // wait-load: the script pauses until the loads end or the deadline passes; the frames spent
  // waiting do not count on the script's clock, so `wait N` after it counts from the load's end.
  std::optional<std::chrono::steady_clock::time_point> script_deadline;
};

// Queues `paths` (read with `array`, empty: none) and starts the first if nothing runs.
void open_datasets(ViewerSession& s, const std::vector<std::string>& paths, const std::string& array = {});
// Cancels the running load and drops the queued ones.
void cancel_loads(ViewerSession& s);
// Once a frame: takes a finished job's result into the scene (or shows its error), starts the
// next, and refreshes what the Data section shows.
void poll_loads(ViewerSession& s);
// Replaces the renderer when the drawn scene is not the mesh it holds (no frame in flight).
void sync_renderer(ViewerSession& s);
// The Data section's requests: open, cancel, show, active.
void apply_data_requests(ViewerSession& s, const DataRequests& r);
// Whether the script waits (wait-load) at this frame; ends the wait when the loads are over or
// its deadline passed.
bool script_waiting(ViewerSession& s);
void begin_script_wait(ViewerSession& s, double timeout_seconds);

}  // namespace prismoid::app
