#include "app/viewer/present_thread.hpp"

#include <stdexcept>
#include <utility>

namespace prismoid::app {

PresentThread::PresentThread() : thread_([this] { run(); }) {}

PresentThread::~PresentThread() {
  {
    std::unique_lock lock(mutex_);
    wake_.wait(lock, [&] { return !work_; });  // a frame being presented ends first
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void PresentThread::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || work_; });
    if (!work_) return;  // stopped with nothing handed over
    std::function<bool()> work = work_;
    lock.unlock();
    bool result = true;
    std::exception_ptr error;
    try {
      result = work();
    } catch (...) {  // given to the loop's thread by poll() or wait()
      error = std::current_exception();
    }
    lock.lock();
    result_ = result;
    error_ = error;
    done_ = true;
    work_ = nullptr;
    wake_.notify_all();
  }
}

void PresentThread::hand_over(std::function<bool()> work) {
  if (handed_) throw std::logic_error("PresentThread: a frame is already handed over");
  {
    std::lock_guard lock(mutex_);
    done_ = false;
    work_ = std::move(work);
  }
  handed_ = true;
  wake_.notify_all();
}

bool PresentThread::take() {
  handed_ = false;
  done_ = false;
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  return result_;
}

std::optional<bool> PresentThread::poll() {
  if (!handed_) return std::nullopt;
  std::lock_guard lock(mutex_);
  if (!done_) return std::nullopt;
  return take();
}

bool PresentThread::wait() {
  if (!handed_) return true;
  std::unique_lock lock(mutex_);
  wake_.wait(lock, [&] { return done_; });
  return take();
}

}  // namespace prismoid::app
