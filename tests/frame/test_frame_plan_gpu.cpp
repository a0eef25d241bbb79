// The frame planner on the GPU: a pass the plan leaves out never runs (no timestamp pair, its
// pipelines never made, its output buffer untouched), and a still camera's reused order
// gives the very image a frame that orders again gives.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstring>
#include <vector>

#include "renderer/frame/backend_choice.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/volume/mesh/visibility_sort.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

constexpr uint32_t kSentinel = 0xFFFFFFFFu;  // no key the keys pass writes (it would encode a NaN)

class FramePlanGpuTest : public test::GpuTest {
 protected:
  static std::vector<std::string> names(const std::vector<vk::PassTiming>& passes) {
    std::vector<std::string> v;
    for (const auto& p : passes) v.push_back(p.name);
    return v;
  }
  static bool ran(const frame::OffscreenFrame& f, const std::string& name) {
    const auto n = names(f.passes);
    const bool cpu = std::any_of(f.report.cpu_passes.begin(), f.report.cpu_passes.end(), [&](const auto& p) { return p.name == name; });
    return cpu || std::find(n.begin(), n.end(), name) != n.end();
  }
  static std::string skip_reason(const frame::FramePlan& plan, const std::string& name) {
    for (const auto& s : plan.skipped)
      if (s.name == name) return s.reason;
    return "";
  }

  // The sort's key buffer: overwritten with the sentinel, and read back.
  void fill_keys(const volume::VisibilitySort& sort) {
    device().submit_and_wait([&](VkCommandBuffer cmd) {
      vk::buffer_barrier(cmd, {sort.keys().get()}, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                         VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
      vkCmdFillBuffer(cmd, sort.keys().get(), 0, VK_WHOLE_SIZE, kSentinel);
      vk::buffer_barrier(cmd, {sort.keys().get()}, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                         VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    });
  }
  std::vector<uint32_t> read_keys(const volume::VisibilitySort& sort, size_t count) {
    vk::Buffer host(device(), count * sizeof(uint32_t), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
    device().submit_and_wait([&](VkCommandBuffer cmd) {
      vk::buffer_barrier(cmd, {sort.keys().get()}, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT,
                         VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
      const VkBufferCopy region{0, 0, count * sizeof(uint32_t)};
      vkCmdCopyBuffer(cmd, sort.keys().get(), host.get(), 1, &region);
    });
    std::vector<uint32_t> keys(count);
    std::memcpy(keys.data(), host.mapped(), count * sizeof(uint32_t));
    return keys;
  }

  static frame::FrameSettings colour(frame::Ordering ordering) {
    frame::FrameSettings s;
    s.resolve.quantity = volume::Quantity::Color;
    s.resolve.transfer = volume::preset("viridis");
    s.resolve.transfer.opacity = {{0.0, 0.0}, {0.2, 0.3}, {0.6, 0.8}, {1.0, 1.0}};
    s.resolve.transfer.range_lo = 0.0;
    s.resolve.transfer.range_hi = 6.0;
    s.resolve.transfer.density_scale = 25.0;  // optical depths of several units: order matters
    s.ordering = ordering;
    return s;
  }
  static Camera oblique(const TetMesh& mesh) {
    Camera c = fit_camera(bounds_of(mesh));
    c.eye = c.target + glm::dvec3(-3.0, 2.0, -3.5);  // mesh order is far from back to front here
    return c;
  }
};

// Optical depth asked for with the GPU sort: the plan leaves the sort out, and it never runs:
// no timestamp pair, and the sort object (its pipelines, hence any bind of them) never made.
// The same renderer then renders colour, where the same checks see the sort (they can fail).
TEST_F(FramePlanGpuTest, ASkippedSortNeverRunsOnTheGpu) {
  const TetMesh mesh = make_default_volume();
  frame::FrameRenderer renderer(device(), mesh);
  frame::FrameSettings settings;
  settings.resolve.quantity = volume::Quantity::OpticalDepth;
  settings.ordering = frame::Ordering::GpuSort;
  const Camera camera = oblique(mesh);
  const auto depth = renderer.render_offscreen(camera, settings, {24, 16});
  EXPECT_EQ(names(depth.passes), (std::vector<std::string>{"interval-shading", "resolve"}));
  EXPECT_EQ(names(depth.passes), depth.report.plan.gpu_pass_names());
  EXPECT_FALSE(ran(depth, "sort"));
  EXPECT_EQ(renderer.gpu_sort(), nullptr) << "the sort's pipelines were made for a frame that plans no sort";
  EXPECT_NE(skip_reason(depth.report.plan, "sort").find("order-independent"), std::string::npos);

  const auto sorted = renderer.render_offscreen(camera, colour(frame::Ordering::GpuSort), {24, 16});
  EXPECT_EQ(names(sorted.passes), (std::vector<std::string>{"sort", "interval-shading (emission)", "resolve"}));
  EXPECT_EQ(names(sorted.passes), sorted.report.plan.gpu_pass_names());
  ASSERT_NE(renderer.gpu_sort(), nullptr);
}

// A still camera draws with the order the last frame sorted: no sort pass, the sort's keys
// (overwritten with a sentinel in between) untouched by the GPU, and the image bit-identical
// to a fresh renderer's frame that sorts. The order depends only on the eye, so turning the
// camera about it reuses the order too. Moving the eye sorts again (the sentinel is gone).
TEST_F(FramePlanGpuTest, AStillCameraReusesTheSortedOrderWithTheSameImage) {
  const TetMesh mesh = make_default_volume();
  const frame::FrameSettings settings = colour(frame::Ordering::GpuSort);
  frame::FrameRenderer renderer(device(), mesh);
  const Camera camera = oblique(mesh);
  const auto first = renderer.render_offscreen(camera, settings, {40, 30});
  ASSERT_TRUE(ran(first, "sort"));
  ASSERT_NE(renderer.gpu_sort(), nullptr);
  fill_keys(*renderer.gpu_sort());

  Camera turned = camera;
  turned.target += glm::dvec3(0.05, -0.03, 0.02);  // same eye, another view direction
  for (const Camera& still : {camera, turned}) {
    const auto reused = renderer.render_offscreen(still, settings, {40, 30});
    EXPECT_FALSE(ran(reused, "sort"));
    EXPECT_TRUE(reused.report.plan.reuses_order);
    EXPECT_EQ(skip_reason(reused.report.plan, "sort").rfind("order reused: camera still", 0), 0u);
    EXPECT_NE(reused.report.ordering.find("reused"), std::string::npos) << reused.report.ordering;
    const auto keys = read_keys(*renderer.gpu_sort(), mesh.tets.size());
    EXPECT_TRUE(std::all_of(keys.begin(), keys.end(), [](uint32_t k) { return k == kSentinel; })) << "the sort ran on the GPU";

    frame::FrameRenderer fresh(device(), mesh);
    const auto resorted = fresh.render_offscreen(still, settings, {40, 30});
    ASSERT_TRUE(ran(resorted, "sort"));
    EXPECT_EQ(reused.emission, resorted.emission) << "the reused order drew another image than a fresh sort";
    EXPECT_EQ(reused.display, resorted.display);
  }

  Camera moved = camera;
  moved.eye += glm::dvec3(0.2, 0.0, 0.0);
  const auto after_move = renderer.render_offscreen(moved, settings, {40, 30});
  EXPECT_TRUE(ran(after_move, "sort"));
  const auto keys = read_keys(*renderer.gpu_sort(), mesh.tets.size());
  EXPECT_TRUE(std::none_of(keys.begin(), keys.end(), [](uint32_t k) { return k == kSentinel; }));

  renderer.forget_history();  // benchmarks: every frame costs what a moving camera's does
  EXPECT_TRUE(ran(renderer.render_offscreen(moved, settings, {40, 30}), "sort"));
}

// The exact order likewise: a still camera neither recomputes it on the CPU nor uploads it,
// and draws the same image as a frame that does both.
TEST_F(FramePlanGpuTest, AStillCameraReusesTheExactOrderWithTheSameImage) {
  const TetMesh mesh = make_default_volume();
  const frame::FrameSettings settings = colour(frame::Ordering::Exact);
  frame::FrameRenderer renderer(device(), mesh);
  const Camera camera = oblique(mesh);
  const auto first = renderer.render_offscreen(camera, settings, {40, 30});
  ASSERT_TRUE(ran(first, "exact-order"));
  ASSERT_TRUE(ran(first, "upload-order"));
  const auto reused = renderer.render_offscreen(camera, settings, {40, 30});
  EXPECT_FALSE(ran(reused, "exact-order"));
  EXPECT_FALSE(ran(reused, "upload-order"));
  EXPECT_FALSE(ran(reused, "transfer-function upload")) << "the transfer function did not change";
  EXPECT_EQ(names(reused.passes), (std::vector<std::string>{"interval-shading (emission)", "resolve"}));
  EXPECT_TRUE(reused.report.order_exact);
  EXPECT_EQ(reused.emission, first.emission);

  frame::FrameRenderer fresh(device(), mesh);
  const auto recomputed = fresh.render_offscreen(camera, settings, {40, 30});
  EXPECT_EQ(reused.emission, recomputed.emission);

  // Another ordering in between: its order is not the exact one, so the exact order is made again.
  renderer.render_offscreen(camera, colour(frame::Ordering::GpuSort), {40, 30});
  EXPECT_TRUE(ran(renderer.render_offscreen(camera, settings, {40, 30}), "upload-order"));
}

// `auto` picks the backend its calibration measured faster, says so with the numbers, and
// falls back to the mesh-shader backend where a time is missing.
TEST(BackendChoice, PicksTheFasterBackendWithItsNumbers) {
  frame::BackendCalibration c{"dev", {{"mesh", 10.0}, {"compute", 2.5}}, 10368, 128, 128};
  auto choice = frame::choose_backend(c);
  EXPECT_EQ(choice.backend, frame::IntervalBackend::Compute);
  EXPECT_NE(choice.reason.find("4x faster"), std::string::npos) << choice.reason;
  EXPECT_NE(choice.reason.find("10368-cell"), std::string::npos) << choice.reason;
  c.ms["compute"] = 30.0;
  choice = frame::choose_backend(c);
  EXPECT_EQ(choice.backend, frame::IntervalBackend::Mesh);
  EXPECT_NE(choice.reason.find("3x faster"), std::string::npos) << choice.reason;
  c.ms["compute"] = std::numeric_limits<double>::quiet_NaN();
  choice = frame::choose_backend(c);
  EXPECT_EQ(choice.backend, frame::IntervalBackend::Mesh);
  EXPECT_NE(choice.reason.find("could not time"), std::string::npos) << choice.reason;
}

// The calibration times both backends on this device, and its choice is the faster one.
TEST_F(FramePlanGpuTest, CalibrationTimesBothBackends) {
  const frame::BackendCalibration c = frame::calibrate_backends(device(), 1);
  EXPECT_EQ(c.device_key, frame::device_key(device()));
  EXPECT_EQ(c.cells, 10368u);
  const double mesh_ms = c.ms.at("mesh"), compute_ms = c.ms.at("compute");
  ASSERT_TRUE(std::isfinite(mesh_ms) && mesh_ms > 0.0) << mesh_ms;
  ASSERT_TRUE(std::isfinite(compute_ms) && compute_ms > 0.0) << compute_ms;
  EXPECT_EQ(frame::choose_backend(c).backend, compute_ms < mesh_ms ? frame::IntervalBackend::Compute : frame::IntervalBackend::Mesh);
}

}  // namespace
}  // namespace prismoid
