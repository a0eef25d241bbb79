#include <gtest/gtest.h>

#include <cmath>

#include "renderer/frame/frame_renderer.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

class TimerTest : public test::GpuTest {};

TEST_F(TimerTest, EveryRecordedPassReportsAFiniteNonNegativeTime) {
  frame::FrameRenderer renderer(device(), make_default_volume());
  const auto frame = renderer.render_offscreen(fit_camera(renderer.bounds()), {}, {64, 64});
  ASSERT_EQ(frame.passes.size(), 2u);
  EXPECT_EQ(frame.passes[0].name, "interval-shading");
  EXPECT_EQ(frame.passes[1].name, "resolve");
  for (const auto& p : frame.passes) {
    ASSERT_TRUE(device().capabilities().timestamps);
    EXPECT_TRUE(std::isfinite(p.gpu_ms)) << p.name;
    EXPECT_GE(p.gpu_ms, 0.0) << p.name;
  }
}

TEST_F(TimerTest, NestedPassesAreRefused) {
  vk::GpuTimer timer(device(), 4);
  device().submit_and_wait([&](VkCommandBuffer cmd) {
    timer.reset(cmd);
    timer.begin(cmd, "outer");
    EXPECT_THROW(timer.begin(cmd, "inner"), std::logic_error);
    timer.end(cmd);
  });
  EXPECT_EQ(timer.read().size(), 1u);
}

}  // namespace
}  // namespace prismoid
