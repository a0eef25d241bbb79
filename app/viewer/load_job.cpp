#include "app/viewer/load_job.hpp"

#include <exception>

#include "scene/input_error.hpp"

namespace prismoid::app {

DatasetLoad::DatasetLoad(LoadRequest request)
    : request_(std::move(request)), start_(std::chrono::steady_clock::now()), thread_([this] { run(); }) {}

DatasetLoad::~DatasetLoad() {
  cancel_ = true;
  if (thread_.joinable()) thread_.join();
}

std::string DatasetLoad::stage() const {
  const std::lock_guard lock(mutex_);
  return stage_;
}

double DatasetLoad::seconds() const {
  const auto end = done_ ? end_ : std::chrono::steady_clock::now();
  return std::chrono::duration<double>(end - start_).count();
}

LoadOutcome DatasetLoad::take() {
  const std::lock_guard lock(mutex_);
  return std::move(outcome_);
}

void DatasetLoad::run() {
  const io::Progress progress = [this](double fraction, const std::string& stage) {
    fraction_ = fraction;
    {
      const std::lock_guard lock(mutex_);
      stage_ = stage;
    }
    return !cancel_;
  };
  LoadOutcome outcome;
  try {
    TetMesh mesh = load_dataset(request_, progress);
    // Loads that never report (the generated datasets) still stop here when cancelled.
    if (cancel_) throw io::Cancelled(request_.path);
    if (mesh.name.empty()) mesh.name = request_.path;
    validate(mesh);
    progress(1.0, "measuring");
    outcome.dataset = make_dataset(std::move(mesh), field_of_request(request_));
    attach_time(*outcome.dataset, request_);
  } catch (const io::Cancelled& e) {
    outcome.cancelled = true;
    outcome.error = e.what();
  } catch (const InputError& e) {  // names the file and the problem
    outcome.error = e.what();
  } catch (const std::exception& e) {  // out of memory, a failed fork...: say for which file
    outcome.error = request_.path + ": " + e.what();
  } catch (...) {
    outcome.error = request_.path + ": loading failed";
  }
  {
    const std::lock_guard lock(mutex_);
    outcome_ = std::move(outcome);
    end_ = std::chrono::steady_clock::now();
  }
  done_ = true;
}

}  // namespace prismoid::app
