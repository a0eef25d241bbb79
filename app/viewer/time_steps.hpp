#pragma once
// Internal to the viewer: stepping and playing through time (issue "Simulations as they come").
// The active dataset's other steps load on a thread of their own (DatasetLoad, the request that
// opened it at another --time-step), never on the frame loop's: the step shown changes once its
// step has loaded, and while playing the next step is read ahead. A step whose points and cells
// are those drawn sends only its fields to the GPU (sync_renderer: FrameRenderer::update_fields).
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "app/viewer/load_job.hpp"
#include "app/viewer/view_state.hpp"

namespace prismoid::app {

struct ViewerSession;

struct TimeStepping {
  struct Job {
    size_t dataset = 0;
    uint32_t step = 0;
    std::unique_ptr<DatasetLoad> load;
  };
  std::unique_ptr<Job> job;          // one step loading at a time
  std::vector<Job> ready;            // loaded steps not shown yet (read ahead), their loads done
  std::optional<uint32_t> wanted;    // the step asked for, shown once it has loaded
  bool playing = false;
  // While playing, a step stays on screen at least this long (and until the next has loaded).
  double seconds_per_step = 0.5;
  std::chrono::steady_clock::time_point shown_at{};
  std::optional<uint32_t> waiting_for;  // a script's wait-step: its commands pause until this step is shown
  std::unique_ptr<Job> compare_job;     // split view's B at another step, loading
  size_t compare_dataset = 0;           // the dataset whose step B shows (ViewState::compare_step)
};

// Asks for step `step` of the active dataset (a time series or an Exodus file with steps); the
// message says why not (none, or no such step), else empty.
std::string go_to_step(ViewerSession& s, uint32_t step);
// Starts or stops playing the active dataset's steps (from the last back to the first).
std::string set_playing(ViewerSession& s, bool playing);
// Once a frame: a finished step load shown or kept, the next step read ahead while playing, the
// Time section's numbers refreshed.
void poll_time(ViewerSession& s);
// Split view's B at step `step` of the active dataset (loaded on its own thread; the view turns to
// split when it has loaded), or (none) at the step A shows. The message says why not, else empty.
std::string set_compare_step(ViewerSession& s, std::optional<uint32_t> step);
// Whether a step is loading or asked for and not shown yet (a script's wait-load waits for it).
bool time_loading(const ViewerSession& s);

}  // namespace prismoid::app
