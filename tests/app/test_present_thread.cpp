// The window's present thread (app/viewer/present_thread.hpp): the frame's submission and
// presentation run beside the loop, which goes on reading input until they end.
#include <gtest/gtest.h>

#include <atomic>
#include <future>
#include <stdexcept>
#include <thread>

#include "app/viewer/present_thread.hpp"

namespace prismoid {
namespace {

TEST(PresentThread, TheCallerGoesOnWhileTheWorkRunsAndGetsItsResultOnce) {
  app::PresentThread presenter;
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  std::atomic<std::thread::id> ran_on{};
  presenter.hand_over([&] {
    ran_on = std::this_thread::get_id();
    released.wait();  // a frame that takes as long as the caller wants
    return false;
  });
  EXPECT_TRUE(presenter.handed());
  // The caller is not held: it polls many times while the work is blocked.
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(presenter.poll().has_value());
  EXPECT_THROW(presenter.hand_over([] { return true; }), std::logic_error);  // one frame at a time
  release.set_value();
  EXPECT_FALSE(presenter.wait());  // the work's own result
  EXPECT_NE(ran_on.load(), std::this_thread::get_id());
  EXPECT_FALSE(presenter.handed());
  EXPECT_FALSE(presenter.poll().has_value());  // given once
  EXPECT_TRUE(presenter.wait());               // nothing handed over
}

TEST(PresentThread, PollSeesTheEndAndTheNextFrameCanBeHandedOver) {
  app::PresentThread presenter;
  for (int frame = 0; frame < 50; ++frame) {
    presenter.hand_over([frame] { return frame % 2 == 0; });
    std::optional<bool> result;
    while (!(result = presenter.poll())) std::this_thread::yield();
    EXPECT_EQ(*result, frame % 2 == 0);
  }
}

TEST(PresentThread, WhatTheWorkThrowsComesBackToTheCaller) {
  app::PresentThread presenter;
  presenter.hand_over([]() -> bool { throw std::runtime_error("vkQueueSubmit: VK_ERROR_DEVICE_LOST"); });
  EXPECT_THROW(presenter.wait(), std::runtime_error);
  EXPECT_FALSE(presenter.handed());
  presenter.hand_over([] { return true; });  // and the thread goes on
  EXPECT_TRUE(presenter.wait());
}

TEST(PresentThread, DestroyingItWaitsForTheFrameHandedOver) {
  std::atomic<bool> finished{false};
  {
    app::PresentThread presenter;
    presenter.hand_over([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      finished = true;
      return true;
    });
  }
  EXPECT_TRUE(finished);
}

}  // namespace
}  // namespace prismoid
