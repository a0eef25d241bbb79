// The shared plumbing of the verbs, the window and the bench (app/common) that runs without a GPU.
#include <chrono>
#include <cmath>
#include <thread>

#include <gtest/gtest.h>

#include "app/common/warm_up.hpp"

namespace prismoid::app {
namespace {

// Warm-up frames run for the time asked, and at least once (the first frame's pipelines and
// caches are never timed); past that time they go on while the frames still get faster (a GPU
// raising its clock), up to 4x the time.
TEST(WarmUp, FramesRunForTheTimeAskedAndWhileTheyGetFaster) {
  uint32_t calls = 0;
  EXPECT_EQ(warm_up([&] { return double(++calls); }, 0.0), 1u);
  EXPECT_EQ(calls, 1u);
  const auto seconds_of = [](const auto& f) {
    const auto start = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  auto sleepy = [](double ms) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    return ms;
  };
  // Steady frames: the time asked, then done.
  uint32_t steady = 0;
  const double steady_s = seconds_of([&] { steady = warm_up([&] { return sleepy(10.0); }, 0.1); });
  EXPECT_GE(steady_s, 0.1);
  EXPECT_LT(steady_s, 0.3);
  EXPECT_GE(steady, 8u);
  EXPECT_LT(steady, 60u);
  // Frames 10% faster each time for 60 frames, then steady: past the time asked until they settle.
  calls = 0;
  double ms = 100.0;
  const uint32_t settling = warm_up([&] { ++calls; if (calls <= 60) ms *= 0.9; return sleepy(ms); }, 0.1);
  EXPECT_GE(settling, 60u);
  EXPECT_LE(settling, 72u);
  // Frames without a time (a device without timestamps) stop at the time asked.
  const double untimed_s = seconds_of([&] { warm_up([&] { return sleepy(std::nan("")); }, 0.05); });
  EXPECT_GE(untimed_s, 0.05);
  EXPECT_LT(untimed_s, 0.15);
  // Frames that always get faster stop at 4x the time.
  ms = 1e30;
  const double capped_s = seconds_of([&] { warm_up([&] { ms *= 0.5; return sleepy(ms); }, 0.05); });
  EXPECT_GE(capped_s, 0.2);
  EXPECT_LT(capped_s, 0.5);
}

}  // namespace
}  // namespace prismoid::app
