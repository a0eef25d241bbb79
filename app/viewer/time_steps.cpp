#include "app/viewer/time_steps.hpp"

#include <algorithm>

#include "app/viewer/compare.hpp"
#include "app/viewer/dataset_list.hpp"
#include "app/viewer/viewer_session.hpp"

namespace prismoid::app {

namespace {

// A step is kept read ahead only while its dataset is the active one: a dataset made active,
// or another step asked for, drops what no longer follows.
constexpr size_t kReadAhead = 2;

// Step `step` of the active dataset, loading: the request that opened it, at that step.
std::unique_ptr<TimeStepping::Job> load_step(const ViewerSession& s, uint32_t step) {
  LoadRequest r = *s.state.dataset().source;
  r.time_step = step;
  r.time.reset();
  return std::make_unique<TimeStepping::Job>(TimeStepping::Job{s.state.active, step, std::make_unique<DatasetLoad>(std::move(r))});
}

// Why `verb` cannot show step `step` of `d` (it has none, or not that one); empty when it can.
std::string step_problem(const Dataset& d, const std::string& verb, uint32_t step) {
  if (d.times.empty() || !d.source) return verb + ": " + d.name + " has no time steps";
  if (step >= d.times.size())
    return verb + ": " + d.source->path + " has " + std::to_string(d.times.size()) + " steps (0 to " + std::to_string(d.times.size() - 1) +
           "), not " + std::to_string(step);
  return {};
}

bool loading_or_ready(const TimeStepping& t, size_t dataset, uint32_t step) {
  if (t.job && t.job->dataset == dataset && t.job->step == step) return true;
  return std::any_of(t.ready.begin(), t.ready.end(), [&](const TimeStepping::Job& j) { return j.dataset == dataset && j.step == step; });
}

// Shows a loaded step: in its dataset's place, or its error in the panel.
void show(ViewerSession& s, TimeStepping::Job& job) {
  LoadOutcome outcome = job.load->take();
  if (!outcome.dataset) {
    s.failed("Could not load the time step", outcome.error);
    return;
  }
  s.message(show_step(s.state, job.dataset, std::move(*outcome.dataset)));
  s.report.steps_shown.push_back(job.step);
  s.time.shown_at = std::chrono::steady_clock::now();
}

uint32_t next_step(const Dataset& d) { return d.step + 1 < d.times.size() ? d.step + 1 : 0; }

void step_loads(ViewerSession& s);

}  // namespace

std::string go_to_step(ViewerSession& s, uint32_t step) {
  if (std::string problem = step_problem(s.state.dataset(), "time-step", step); !problem.empty()) return problem;
  s.time.wanted = step;
  return {};
}

std::string set_playing(ViewerSession& s, bool playing) {
  const Dataset& d = s.state.dataset();
  if (playing && (d.times.size() < 2 || !d.source)) return "play: " + d.name + " has no time steps to play";
  s.time.playing = playing;
  s.time.shown_at = std::chrono::steady_clock::now();
  return {};
}

void poll_time(ViewerSession& s) {
  step_loads(s);
  s.panel.data.playing = s.time.playing;
  s.panel.data.step_loading = time_loading(s);
}

bool time_loading(const ViewerSession& s) { return s.time.job != nullptr || s.time.wanted.has_value() || s.time.compare_job != nullptr; }

std::string set_compare_step(ViewerSession& s, std::optional<uint32_t> step) {
  s.time.compare_job.reset();
  if (!step) {
    s.state.compare_step.reset();
    s.state.compare_step_mesh.reset();
    return {};
  }
  if (std::string problem = step_problem(s.state.dataset(), "compare-step", *step); !problem.empty()) return problem;
  s.time.compare_job = load_step(s, *step);
  return {};
}

namespace {

// Split view's B step, once loaded: B draws it (the view turns to split, B in A's mode unless B
// has a mode of its own).
void compare_loads(ViewerSession& s) {
  TimeStepping& t = s.time;
  if (!t.compare_job || !t.compare_job->load->done()) return;
  const std::unique_ptr<TimeStepping::Job> job = std::move(t.compare_job);
  LoadOutcome outcome = job->load->take();
  if (!outcome.dataset) {
    s.failed("Could not load the time step", outcome.error);
    return;
  }
  if (job->dataset != s.state.active) return;  // another dataset became active meanwhile
  s.state.compare_step = job->step;
  s.state.compare_step_mesh = outcome.dataset->mesh;
  t.compare_dataset = job->dataset;
  if (s.state.compare_mode.empty()) s.state.compare_mode = s.state.mode;
  if (s.state.compare != CompareMode::Split) s.message(set_compare(s.state, CompareMode::Split));
}

void step_loads(ViewerSession& s) {
  compare_loads(s);
  if (s.state.compare_step && s.time.compare_dataset != s.state.active) {  // B's step was another dataset's
    s.state.compare_step.reset();
    s.state.compare_step_mesh.reset();
  }
  TimeStepping& t = s.time;
  const size_t active = s.state.active;
  // A finished load joins the ready steps (those of another dataset than the active one are dropped).
  if (t.job && t.job->load->done()) {
    if (t.job->dataset == active) t.ready.push_back(std::move(*t.job));
    t.job.reset();
  }
  std::erase_if(t.ready, [&](const TimeStepping::Job& j) { return j.dataset != active || j.dataset >= s.state.datasets.size(); });
  if (active >= s.state.datasets.size()) return;
  const Dataset& d = s.state.dataset();
  if (d.times.empty() || !d.source) {
    t.playing = false;
    t.wanted.reset();
    return;
  }
  // Playing: the next step is wanted once the shown one has been on screen long enough.
  if (t.playing && !t.wanted &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t.shown_at).count() >= t.seconds_per_step)
    t.wanted = next_step(d);
  if (t.wanted && *t.wanted == d.step) t.wanted.reset();
  if (t.wanted) {
    const auto found = std::find_if(t.ready.begin(), t.ready.end(), [&](const TimeStepping::Job& j) { return j.step == *t.wanted; });
    if (found != t.ready.end()) {
      TimeStepping::Job job = std::move(*found);
      t.ready.erase(found);
      t.wanted.reset();
      show(s, job);
    } else if (!t.job) {
      t.job = load_step(s, *t.wanted);
    }
  }
  // Read ahead while playing: the step after the one shown.
  const Dataset& now = s.state.dataset();
  if (t.playing && !t.job && !now.times.empty() && !loading_or_ready(t, active, next_step(now)) && t.ready.size() < kReadAhead)
    t.job = load_step(s, next_step(now));
}

}  // namespace

}  // namespace prismoid::app
