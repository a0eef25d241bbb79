// The window path under a real X server (Xvfb in CI): opens, presents, survives resizing
// and minimizing, closes, with the validation layer silent.
#include <gtest/gtest.h>

#include <cstdlib>

#include "app/viewer.hpp"
#include "scene/generators.hpp"

namespace prismoid {
namespace {

TEST(Viewer, PresentsResizesMinimizesAndClosesWithoutValidationMessages) {
  ASSERT_TRUE(app::display_available()) << "this test needs a display: run it through scripts/test.sh, which starts Xvfb";
  app::ViewerOptions options;
  options.width = 320;
  options.height = 240;
  options.validation = true;
  options.print_timings = false;
  using K = app::ViewerAction::Kind;
  options.script = {
      {K::Resize, 4, 400, 300},
      {K::Iconify, 10, 0, 0},
      {K::Restore, 16, 0, 0},
      {K::Resize, 22, 200, 360},
      {K::Close, 30, 0, 0},
  };
  options.max_frames = 200;  // a safety net: the script closes the window long before
  const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
  // Frames 0..30 run (the close request is seen at the top of frame 31). Without a window
  // manager (plain Xvfb) iconify is a no-op and every frame presents; with one, the
  // minimized frames are skipped instead. Either way each frame is accounted for once.
  EXPECT_GE(report.frames_presented, 15u);
  EXPECT_EQ(report.frames_presented + report.frames_skipped_minimized, 31u);
  EXPECT_GE(report.swapchain_recreations, 2u);
  EXPECT_EQ(report.validation_messages, 0u);
}

// The window draws what render draws: emission-absorption in exact order (a CPU order each
// frame, copied to the GPU while no frame is in flight) and in GPU-sorted order, resizing
// mid-way (new targets), with the validation layer silent.
TEST(Viewer, ColourInEachOrderingPresentsWithoutValidationMessages) {
  ASSERT_TRUE(app::display_available()) << "this test needs a display: run it through scripts/test.sh, which starts Xvfb";
  for (const auto ordering : {frame::Ordering::Exact, frame::Ordering::GpuSort}) {
    app::ViewerOptions options;
    options.width = 160;
    options.height = 120;
    options.validation = true;
    options.print_timings = false;
    options.settings.resolve.quantity = volume::Quantity::Color;
    options.settings.resolve.transfer.range_hi = 6.0;
    options.settings.ordering = ordering;
    using K = app::ViewerAction::Kind;
    options.script = {{K::Resize, 3, 200, 150}, {K::Close, 8, 0, 0}};
    options.max_frames = 100;
    const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
    EXPECT_GE(report.frames_presented, 5u);
    EXPECT_EQ(report.validation_messages, 0u);
  }
}

}  // namespace
}  // namespace prismoid
