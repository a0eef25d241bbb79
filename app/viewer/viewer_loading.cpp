#include "app/viewer/viewer_loading.hpp"

#include <algorithm>
#include <filesystem>
#include <utility>

#include "app/viewer/dataset_list.hpp"
#include "app/viewer/recent_files.hpp"
#include "app/viewer/viewer_session.hpp"

namespace prismoid::app {

namespace {

void start_next(ViewerSession& s) {
  LoadingState& l = s.loading;
  if (l.job || l.queue.empty()) return;
  l.job = std::make_unique<DatasetLoad>(std::move(l.queue.front()));
  l.queue.pop_front();
  l.frames_at_start = s.report.frames_presented;
}

void refresh_recent(ViewerSession& s) {
  s.panel.data.recent.clear();
  for (const std::string& path : s.loading.recent) {
    std::error_code error;
    s.panel.data.recent.push_back({path, std::filesystem::exists(path, error)});
  }
}

// A finished job: into the scene, or its message in the panel and the popup.
void finish(ViewerSession& s, DatasetLoad& job) {
  LoadOutcome outcome = job.take();
  LoadRecord record;
  record.path = job.request().path;
  record.seconds = job.seconds();
  record.frames_presented = s.report.frames_presented - s.loading.frames_at_start;
  record.cancelled = outcome.cancelled;
  if (outcome.dataset) {
    record.loaded = true;
    record.cells = outcome.dataset->mesh->tets.size();
    s.panel.message = "opened " + record.path;
    s.message(add_dataset(s.state, std::move(*outcome.dataset)));  // a note when the mode had to change
    s.loading.fit_camera = true;
    if (!s.loading.recent_file.empty()) {
      s.loading.recent = remember_opened(s.loading.recent_file, record.path);
      refresh_recent(s);
    }
  } else {
    record.error = outcome.error;
    s.report.last_load_error = outcome.error;
    if (outcome.cancelled) {
      ++s.report.loads_cancelled;
      s.message(outcome.error);
    } else {
      s.message("could not open: " + outcome.error);
      s.panel.data.error = outcome.error;
      s.panel.data.error_title = "Could not open";
      s.panel.data.show_error = true;
      s.report.error_popups.push_back("Could not open: " + outcome.error);
    }
  }
  s.report.loads.push_back(std::move(record));
}

}  // namespace

void open_datasets(ViewerSession& s, const std::vector<std::string>& paths, const std::string& array) {
  for (const std::string& path : paths) {
    s.inputs.push_back(path);  // read from now on: no output of the window may replace it
    LoadRequest r = s.loading.defaults;
    r.path = path;
    r.array = array;
    s.loading.queue.push_back(std::move(r));
  }
  start_next(s);
}

void cancel_loads(ViewerSession& s) {
  s.loading.queue.clear();
  if (s.loading.job) s.loading.job->cancel();
}

void poll_loads(ViewerSession& s) {
  LoadingState& l = s.loading;
  if (!l.recent_read && !l.recent_file.empty()) {
    l.recent_read = true;
    l.recent = read_recent(l.recent_file);
    refresh_recent(s);
  }
  if (l.job && l.job->done()) {
    finish(s, *l.job);
    l.job.reset();
    start_next(s);
  }
  LoadStatus& status = s.panel.data.load;
  status.running = l.job != nullptr;
  if (!l.job) return;
  status.label = load_label(l.job->request());
  status.fraction = l.job->fraction();
  status.stage = l.job->stage();
  status.seconds = l.job->seconds();
  status.queued = l.queue.size();
}

void sync_renderer(ViewerSession& s) {
  LoadingState& l = s.loading;
  const std::shared_ptr<const TetMesh>& mesh = s.state.drawn().mesh;
  if (!l.renderer_slot || mesh == l.drawn_mesh) return;
  // A time step of the mesh drawn: its fields alone go to the GPU, and the camera stays.
  if (l.renderer_slot->has_value() && (*l.renderer_slot)->update_fields(*mesh)) {
    l.drawn_mesh = mesh;
    ++s.report.field_uploads;
    s.stats.report().counted = false;
    return;
  }
  s.device.wait_idle();
  // The new renderer takes the old one's place: references to it (the session's, the loop's)
  // then name the new object, as C++ allows for a same-type object in the same storage.
  l.renderer_slot->reset();
  l.renderer_slot->emplace(s.device, *mesh);
  ++s.report.mesh_uploads;
  l.drawn_mesh = mesh;
  const bool flying = s.camera.flying();
  s.camera = CameraController(s.state.drawn().bounds, s.camera.camera());
  s.camera.set_flying(flying);
  if (std::exchange(l.fit_camera, false)) s.camera.reset(s.aspect());  // a dataset was added: show all of the scene
  s.stats.cells = mesh->tets.size();
  s.stats.report().counted = false;
}

void apply_data_requests(ViewerSession& s, const DataRequests& r) {
  if (r.cancel) cancel_loads(s);
  if (r.show) s.message(show_dataset(s.state, r.show->first, r.show->second));
  if (r.make_active) s.message(set_active(s.state, *r.make_active));
  if (r.time_step) s.message(go_to_step(s, *r.time_step));
  if (r.play) s.message(set_playing(s, *r.play));
  if (r.range_per_step) s.state.range_per_step = *r.range_per_step;
  if (r.compare_step) s.message(set_compare_step(s, *r.compare_step));
  if (!r.open.empty()) open_datasets(s, r.open, r.array);
}

void begin_script_wait(ViewerSession& s, double timeout_seconds) {
  s.loading.script_deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                                    std::chrono::duration<double>(timeout_seconds));
}

bool script_waiting(ViewerSession& s) {
  LoadingState& l = s.loading;
  if (!l.script_deadline) return false;
  const std::optional<uint32_t> step = s.time.waiting_for;
  const bool waiting = step ? s.state.dataset().step != *step : l.job || !l.queue.empty() || time_loading(s);
  if (waiting && std::chrono::steady_clock::now() < *l.script_deadline) return true;
  if (waiting)
    s.message(step ? "wait-step: step " + std::to_string(*step) + " was not shown before the timeout"
                   : std::string("wait-load: the load did not end before the timeout"));
  l.script_deadline.reset();
  s.time.waiting_for.reset();
  return false;
}

}  // namespace prismoid::app
