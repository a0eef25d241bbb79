#pragma once
// A frame's submission and presentation, run on a thread of its own so that the window loop
// keeps reading input while the frame is drawn. On lavapipe the whole frame is drawn inside
// vkQueueSubmit and vkQueuePresentKHR on the calling thread (a full frame of 200k cells at
// 1280x800 takes seconds there); on a GPU they return at once and the frame's fence says when
// the drawing ends. While a frame is handed over, the queue is this thread's: the loop uses the
// queue (uploads, waits for idle, swapchain recreation) only once poll() has given the result.
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <optional>
#include <thread>

namespace prismoid::app {

class PresentThread {
 public:
  PresentThread();
  // Waits for the work handed over (its result and exception are dropped), then ends the thread.
  ~PresentThread();
  PresentThread(const PresentThread&) = delete;
  PresentThread& operator=(const PresentThread&) = delete;

  // Runs `work` on the thread; none may be handed over (handed() false). Its bool is the
  // caller's (for the window: whether the swapchain is still current).
  void hand_over(std::function<bool()> work);
  // Whether work was handed over and its result not yet taken.
  bool handed() const { return handed_; }
  // The work's result once it has ended (then handed() is false), nothing while it runs.
  // Rethrows what the work threw.
  std::optional<bool> poll();
  // Waits for the work handed over and returns its result (true when none was); rethrows.
  bool wait();

 private:
  void run();
  bool take();  // under lock, the work ended: its result or its exception

  std::mutex mutex_;
  std::condition_variable wake_;
  std::function<bool()> work_;
  bool done_ = false, stop_ = false, result_ = true;
  std::exception_ptr error_;
  bool handed_ = false;  // the caller's side only
  std::thread thread_;   // last: starts once the members above exist
};

}  // namespace prismoid::app
