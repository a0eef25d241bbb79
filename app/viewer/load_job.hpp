#pragma once
// A dataset loading on its own thread while the window keeps drawing: the job runs
// load_dataset with a progress callback that publishes the fraction and stage and asks to stop
// once cancel() was called; the frame loop polls it once a frame. The result is a Dataset
// ready for the scene (validated, its range measured), or the data layer's message. GPU work
// (uploading the mesh) is left to the thread that owns the device.
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "app/common/dataset_loader.hpp"
#include "app/viewer/view_state.hpp"

namespace prismoid::app {

struct LoadOutcome {
  std::optional<Dataset> dataset;  // when it loaded
  std::string error;               // else why not (InputError's text, "cancelled", ...)
  bool cancelled = false;
};

class DatasetLoad {
 public:
  explicit DatasetLoad(LoadRequest request);
  // Cancels and waits for the thread: a window closed mid-load ends promptly (the io layer checks
  // for cancellation at least ten times a second, and kills TetGen's child process).
  ~DatasetLoad();
  DatasetLoad(const DatasetLoad&) = delete;
  DatasetLoad& operator=(const DatasetLoad&) = delete;

  const LoadRequest& request() const { return request_; }
  void cancel() { cancel_ = true; }
  bool done() const { return done_; }
  // The last progress report: fraction in [0, 1], or negative when unknown (TetGen).
  double fraction() const { return fraction_; }
  std::string stage() const;
  double seconds() const;  // since the job started (until it ended, once done)
  // Once done(): the result (the dataset is moved out; call once).
  LoadOutcome take();

 private:
  void run();

  LoadRequest request_;
  std::chrono::steady_clock::time_point start_, end_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> done_{false};
  std::atomic<double> fraction_{0.0};
  mutable std::mutex mutex_;  // guards stage_ and outcome_
  std::string stage_ = "starting";
  LoadOutcome outcome_;
  std::thread thread_;  // last: starts once everything above exists
};

}  // namespace prismoid::app
