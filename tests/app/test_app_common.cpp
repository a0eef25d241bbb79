// The shared plumbing of the verbs, the window and the bench (app/common) that runs without a GPU.
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>
#include <unistd.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include "app/common/cli_args.hpp"
#include "app/common/frame_stats_writer.hpp"
#include "app/common/stats_json.hpp"
#include "renderer/timing/frame_timing.hpp"
#include "renderer/timing/warm_up.hpp"
#include "scene/bounds.hpp"
#include "scene/camera.hpp"

namespace prismoid::app {
namespace {

// Warm-up frames run for the time asked, and at least once (the first frame's pipelines and
// caches are never timed); past that time they go on while the frames still get faster (a GPU
// raising its clock), up to 4x the time.
// A camera placed by hand keeps nothing of the data before its near plane. The default framing's
// near plane (half its distance to the data's sphere) stood 5.9 in front of an eye placed 3.6 from
// the near corner of a wide floor, and cut away everything nearer (a floor of 8 x 8 seen from
// above its corner showed only its far half).
TEST(CameraOptions, AnEyePlacedByHandSeesTheDataNearestIt) {
  const Bounds floor{{-4.0, -1.05, -4.0}, {4.0, 1.0, 4.0}};
  const ParsedArgs a = parse({"render", "--eye", "2.6,1.7,3.6", "--target", "0,-0.2,0"}, 1, kCameraOptions, {});
  const Camera c = camera_from(a, floor);
  const glm::dvec3 forward = glm::normalize(c.target - c.eye);
  double nearest = 1e300;
  for (int k = 0; k < 8; ++k)
    nearest = std::min(nearest, glm::dot(glm::dvec3{k & 1 ? 4.0 : -4.0, k & 2 ? 1.0 : -1.05, k & 4 ? 4.0 : -4.0} - c.eye, forward));
  EXPECT_GT(c.near_distance, 0.0);
  EXPECT_LE(c.near_distance, 0.5 * std::max(nearest, 0.0) + 1e-3 * floor.radius());
  // Inside the data: a small positive near plane (1/2000 of the radius).
  const ParsedArgs inside = parse({"render", "--eye", "0.1,0,0.2", "--target", "1,0,0"}, 1, kCameraOptions, {});
  EXPECT_NEAR(camera_from(inside, floor).near_distance, 0.5e-3 * floor.radius(), 1e-12);
  // --near given is kept; without --eye or --target the default framing's stays.
  const ParsedArgs given = parse({"render", "--eye", "2.6,1.7,3.6", "--near", "0.7"}, 1, kCameraOptions, {});
  EXPECT_EQ(camera_from(given, floor).near_distance, 0.7);
  EXPECT_EQ(camera_from(parse({"render"}, 1, kCameraOptions, {}), floor).near_distance, fit_camera(floor, 40.0).near_distance);
}

TEST(WarmUp, FramesRunForTheTimeAskedAndWhileTheyGetFaster) {
  uint32_t calls = 0;
  EXPECT_EQ(timing::warm_up([&] { return double(++calls); }, 0.0), 1u);
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
  const double steady_s = seconds_of([&] { steady = timing::warm_up([&] { return sleepy(10.0); }, 0.1); });
  EXPECT_GE(steady_s, 0.1);
  EXPECT_LT(steady_s, 0.3);
  EXPECT_GE(steady, 8u);
  EXPECT_LT(steady, 60u);
  // Frames 10% faster each time for 60 frames, then steady: past the time asked until they settle.
  calls = 0;
  double ms = 100.0;
  const uint32_t settling = timing::warm_up([&] { ++calls; if (calls <= 60) ms *= 0.9; return sleepy(ms); }, 0.1);
  EXPECT_GE(settling, 60u);
  EXPECT_LE(settling, 72u);
  // Frames without a time (a device without timestamps) stop at the time asked.
  const double untimed_s = seconds_of([&] { timing::warm_up([&] { return sleepy(std::nan("")); }, 0.05); });
  EXPECT_GE(untimed_s, 0.05);
  EXPECT_LT(untimed_s, 0.15);
  // Frames that always get faster stop at 4x the time.
  ms = 1e30;
  const double capped_s = seconds_of([&] { timing::warm_up([&] { ms *= 0.5; return sleepy(ms); }, 0.05); });
  EXPECT_GE(capped_s, 0.2);
  EXPECT_LT(capped_s, 0.5);
}


// ---- frame_timing: the one summary of timed frames ----

std::vector<vk::PassTiming> frame_of(std::initializer_list<std::pair<const char*, double>> passes) {
  std::vector<vk::PassTiming> f;
  for (const auto& [name, ms] : passes) f.push_back({name, ms});
  return f;
}

TEST(FrameTiming, MedianOfFiniteValues) {
  EXPECT_EQ(timing::median_of({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(timing::median_of({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(timing::median_of({std::nan(""), 5.0}), 5.0);
  EXPECT_TRUE(std::isnan(timing::median_of({})));
  EXPECT_TRUE(std::isnan(timing::median_of({std::nan("")})));
}

TEST(FrameTiming, EachPassBestMedianWorstOverTheFrames) {
  const timing::FrameTiming t = timing::summarize_frames({frame_of({{"sort", 1.0}, {"intervals", 4.0}, {"resolve", 0.5}}),
                                          frame_of({{"sort", 3.0}, {"intervals", 2.0}, {"resolve", 0.5}}),
                                          frame_of({{"sort", 2.0}, {"intervals", 9.0}, {"resolve", 0.25}})});
  EXPECT_EQ(t.frames, 3u);
  ASSERT_EQ(t.passes.size(), 3u);
  EXPECT_EQ(t.passes[0].name, "sort");
  EXPECT_EQ(t.passes[0].ms.best, 1.0);
  EXPECT_EQ(t.passes[0].ms.median, 2.0);
  EXPECT_EQ(t.passes[0].ms.worst, 3.0);
  EXPECT_EQ(t.passes[1].name, "intervals");
  EXPECT_EQ(t.passes[1].ms.best, 2.0);
  EXPECT_EQ(t.passes[1].ms.median, 4.0);
  EXPECT_EQ(t.passes[1].ms.worst, 9.0);
  EXPECT_EQ(t.passes[2].ms.best, 0.25);
  EXPECT_EQ(t.passes[2].ms.median, 0.5);
  // Totals per frame: 5.5, 5.5, 11.25.
  EXPECT_EQ(t.total_ms.best, 5.5);
  EXPECT_EQ(t.total_ms.median, 5.5);
  EXPECT_EQ(t.total_ms.worst, 11.25);
  EXPECT_FALSE(t.sm_clock.has_value());
  const std::vector<vk::PassTiming> medians = t.medians();
  ASSERT_EQ(medians.size(), 3u);
  EXPECT_EQ(medians[1].name, "intervals");
  EXPECT_EQ(medians[1].gpu_ms, 4.0);
}

// A name that repeats in a frame is two passes; a frame without a pass leaves the others in place.
TEST(FrameTiming, RepeatedNamesStayApartAndMissingPassesShiftNothing) {
  const timing::FrameTiming t = timing::summarize_frames({frame_of({{"gi", 1.0}, {"gi", 10.0}, {"display", 2.0}}),
                                          frame_of({{"gi", 3.0}, {"display", 4.0}}),
                                          frame_of({{"gi", 5.0}, {"gi", 30.0}, {"display", 6.0}})});
  ASSERT_EQ(t.passes.size(), 3u);
  EXPECT_EQ(t.passes[0].ms.median, 3.0);   // the first "gi" of every frame: 1, 3, 5
  EXPECT_EQ(t.passes[1].ms.median, 20.0);  // the second: 10, 30
  EXPECT_EQ(t.passes[2].name, "display");
  EXPECT_EQ(t.passes[2].ms.median, 4.0);
}

TEST(FrameTiming, NoTimestampsGiveNaNNotGarbage) {
  const timing::FrameTiming t = timing::summarize_frames({frame_of({{"a", std::nan("")}}), frame_of({{"a", std::nan("")}})});
  ASSERT_EQ(t.passes.size(), 1u);
  EXPECT_TRUE(std::isnan(t.passes[0].ms.best));
  EXPECT_TRUE(std::isnan(t.passes[0].ms.median));
  EXPECT_TRUE(std::isnan(t.passes[0].ms.worst));
}

// PATH for one test: a folder holding a fake nvidia-smi before the rest of PATH (sh and sleep);
// with no script, that folder alone (no nvidia-smi anywhere). Restored after. The process's clock
// sampler ends on both sides, so that it runs the fake while the fake is on PATH.
class FakePath {
 public:
  explicit FakePath(const std::string& script) {
    dir_ = std::filesystem::temp_directory_path() / ("prismoid-fake-smi-" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
    if (!script.empty()) {
      const std::filesystem::path exe = dir_ / "nvidia-smi";
      std::ofstream(exe) << script;
      std::filesystem::permissions(exe, std::filesystem::perms::owner_all);
    }
    if (const char* p = std::getenv("PATH")) old_ = p;
    setenv("PATH", (script.empty() ? dir_.string() : dir_.string() + ":" + old_).c_str(), 1);
    timing::stop_process_sm_clock();
  }
  ~FakePath() {
    timing::stop_process_sm_clock();
    setenv("PATH", old_.c_str(), 1);
    std::filesystem::remove_all(dir_);
  }

 private:
  std::filesystem::path dir_;
  std::string old_;
};

// nvidia-smi's output, one clock a line; lines that are not a number (a GPU that reports none)
// are no samples. The script prints in one write, and ends in exec so that ending it ends the sleep too.
TEST(SmClock, SamplesAreParsedFromNvidiaSmi) {
  const FakePath path("#!/bin/sh\nprintf '1410\\n1395\\n[N/A]\\n1980\\n'\nexec sleep 30\n");
  const auto start = std::chrono::steady_clock::now();
  timing::SmClockSampler sampler;
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::optional<timing::ClockSpread> clock = sampler.stop();
  ASSERT_TRUE(clock.has_value());
  EXPECT_EQ(clock->samples, 3u);
  EXPECT_EQ(clock->min_mhz, 1395.0);
  EXPECT_EQ(clock->median_mhz, 1410.0);
  EXPECT_EQ(clock->max_mhz, 1980.0);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0) << "stop() ended the child";
}

TEST(SmClock, TimedFramesCarryTheClock) {
  const FakePath path("#!/bin/sh\necho 1500\nexec sleep 30\n");
  uint32_t calls = 0;
  const timing::FrameTiming t = timing::time_frames(3, [&] {
    ++calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return frame_of({{"pass", double(calls)}});
  });
  EXPECT_EQ(calls, 3u);
  EXPECT_EQ(t.frames, 3u);
  ASSERT_EQ(t.passes.size(), 1u);
  EXPECT_EQ(t.passes[0].ms.median, 2.0);
  ASSERT_TRUE(t.sm_clock.has_value());
  EXPECT_EQ(t.sm_clock->median_mhz, 1500.0);
}

// Timed frames shorter than nvidia-smi's period get no sample of their own; the clock they report
// is the one sampled during the warm-up just before, not the idle clock read after them (on the
// H200 that read 345 MHz for rows timed at 1980). The fake models a GPU whose clock is high while
// frames run (a file marks them) and low otherwise, and, like nvidia-smi, takes a while to print
// its first sample.
TEST(SmClock, ShortTimedFramesCarryTheWarmUpsClock) {
  const std::filesystem::path busy = std::filesystem::temp_directory_path() / ("prismoid-busy-" + std::to_string(getpid()));
  const FakePath path("#!/bin/sh\nsleep 0.1\nwhile true; do if [ -e " + busy.string() +
                      " ]; then echo 1980; else echo 345; fi; sleep 0.1; done\n");
  std::ofstream(busy) << "frames run";
  timing::warm_up([] {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    return 1.0;
  }, 0.3);
  uint32_t frames = 0;
  const timing::FrameTiming t = timing::time_frames(2, [&] {
    if (++frames == 2) std::filesystem::remove(busy);  // the GPU idles after the last one
    return frame_of({{"pass", 1.0}});
  });
  std::filesystem::remove(busy);
  ASSERT_TRUE(t.sm_clock.has_value());
  EXPECT_EQ(t.sm_clock->median_mhz, 1980.0);
}

TEST(SmClock, NoNvidiaSmiNoClock) {
  {
    const FakePath path("");  // not on PATH
    timing::SmClockSampler sampler;
    EXPECT_FALSE(sampler.stop().has_value());
  }
  {
    // On PATH but without a driver: an error and no numbers.
    const FakePath path("#!/bin/sh\necho 'NVIDIA-SMI has failed because it could not communicate with the NVIDIA driver.'\nexit 9\n");
    const auto start = std::chrono::steady_clock::now();
    timing::SmClockSampler sampler;
    EXPECT_FALSE(sampler.stop().has_value());
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.5);
  }
}

// ---- stats_json: one layout for every stats file ----

TEST(StatsJson, OneKeyALineObjectsInArraysOneALine) {
  StatsJson js;
  js["device"] = "lavapipe \"quoted\"";
  js["cells"] = 1234;
  js["order_exact"] = true;
  js["march_step"] = 0.1234567891234;
  js["no_time"] = std::nan("");
  js["tf_range"] = {0.0, 2.5};
  js["warnings"] = StatsJson::array();
  js["passes"] = passes_json(timing::summarize_frames({frame_of({{"sort", 1.0}}), frame_of({{"sort", 3.0}}), frame_of({{"sort", 2.0}})}));
  timing::FrameTiming clocked;
  clocked.sm_clock = timing::ClockSpread{1395.0, 1410.0, 1980.0, 3};
  add_sm_clock(js, clocked);
  add_sm_clock(js, timing::FrameTiming{});  // unsampled: nothing set, nothing removed
  EXPECT_EQ(format_stats(js),
            "{\n"
            "  \"device\": \"lavapipe \\\"quoted\\\"\",\n"
            "  \"cells\": 1234,\n"
            "  \"order_exact\": true,\n"
            "  \"march_step\": 0.123456789,\n"
            "  \"no_time\": null,\n"
            "  \"tf_range\": [0, 2.5],\n"
            "  \"warnings\": [],\n"
            "  \"passes\": [\n"
            "    {\"name\": \"sort\", \"gpu_ms\": 2, \"min_ms\": 1, \"max_ms\": 3}\n"
            "  ],\n"
            "  \"sm_clock_mhz\": {\"min\": 1395, \"median\": 1410, \"max\": 1980, \"samples\": 3}\n"
            "}\n");
  // And it is JSON: it reads back to the same values.
  const StatsJson back = StatsJson::parse(format_stats(js));
  EXPECT_EQ(back["device"], "lavapipe \"quoted\"");
  EXPECT_EQ(back["passes"][0]["max_ms"], 3.0);
  EXPECT_TRUE(back["no_time"].is_null());
}

TEST(StatsJson, ThePlanAsEveryVerbWritesIt) {
  frame::FramePlan plan;
  plan.passes.push_back({frame::PassId::Sort, "sort", frame::PassKind::Gpu, "colour is order-dependent"});
  plan.passes.push_back({frame::PassId::ShadowRays, "shadow-rays", frame::PassKind::Within, "a light casts shadows"});
  plan.skipped.push_back({"exact-order", "the GPU sort orders"});
  StatsJson js;
  add_plan(js, plan);
  EXPECT_EQ(format_stats(js),
            "{\n"
            "  \"plan\": [\n"
            "    {\"name\": \"sort\", \"kind\": \"gpu\", \"reason\": \"colour is order-dependent\"},\n"
            "    {\"name\": \"shadow-rays\", \"kind\": \"within\", \"reason\": \"a light casts shadows\"}\n"
            "  ],\n"
            "  \"skipped\": [\n"
            "    {\"pass\": \"exact-order\", \"reason\": \"the GPU sort orders\"}\n"
            "  ]\n"
            "}\n");
}

// A compute-backend volume frame's stats as the facade fills them (numbers chosen, no GPU).
mixed::FrameStats volume_frame() {
  mixed::FrameStats s;
  s.device = "a GPU";
  s.driver = "its driver";
  s.gpu = true;
  s.width = 40;
  s.height = 25;
  mixed::VolumeStats v;
  v.dataset = "ball";
  v.cells = 500;
  v.mode = "interval-sorted";
  v.settings.resolve.quantity = volume::Quantity::OpticalDepth;
  v.settings.backend_reason = "the calibration's numbers";
  v.report.backend = "compute";
  v.report.backend_bytes = 2000;
  v.report.ordering = "per-pixel";
  v.report.order_exact = true;
  v.report.counts_known = true;
  v.report.pairs = 1234;
  v.report.inexact_pixels = 5;
  s.volume = v;
  s.passes = {{"tile-raster", 2.0}, {"resolve", 0.5}};
  return s;
}

// One writer per form: a volume's keys carry the same values alone and inside surfaces, each
// counter is written once (one "pairs" key, one "pairs:" line), and the values are the struct's.
TEST(FrameStatsWriter, AVolumesStatsReadTheSameAloneAndInsideSurfaces) {
  const mixed::FrameStats alone = volume_frame();
  mixed::FrameStats inside = alone;
  inside.mixed = mixed::MixedSurfaceStats{.scene = "square", .triangles = 2, .mode = "forward", .shadows = true};
  const StatsJson a = frame_json(alone, {.image = "a.pfm"});
  const StatsJson b = frame_json(inside, {.image = "b.pfm", .validation_messages = 3});
  EXPECT_EQ(a["pairs"], 1234u);
  EXPECT_EQ(a["backend"], "compute");
  EXPECT_EQ(a["backend_reason"], "the calibration's numbers");
  EXPECT_DOUBLE_EQ(a["backend_bytes_per_cell"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(a["backend_bytes_per_pixel"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(a["gpu_ms_total"].get<double>(), 2.5);
  EXPECT_EQ(a["quantity"], "optical-depth");
  EXPECT_FALSE(a.contains("surfaces"));
  for (const char* key : {"ordering", "order_exact", "backend", "backend_reason", "backend_bytes", "pairs", "inexact_pixels", "tetlet_size",
                          "passes", "gpu_ms_total", "cells", "mode", "quantity"})
    EXPECT_EQ(a[key], b[key]) << key;
  EXPECT_EQ(b["surfaces"], "square");
  EXPECT_EQ(b["surface_mode"], "forward");
  EXPECT_EQ(b["shadows"], true);
  EXPECT_EQ(b["validation_messages"], 3u);

  const auto count = [](const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  const std::string ta = frame_text(alone, {.image = "a.pfm"}), tb = frame_text(inside, {.image = "b.pfm"});
  EXPECT_EQ(ta.rfind("wrote a.pfm (40x25, ball, 500 cells) on a GPU\n", 0), 0u) << ta;
  EXPECT_EQ(tb.rfind("wrote b.pfm (40x25, ball, 500 cells, with square, 2 triangles) on a GPU\n", 0), 0u) << tb;
  for (const std::string& t : {ta, tb}) {
    EXPECT_EQ(count(t, "  pairs: 1234 (tile, cell); pixels composited out of exact order: 5;"), 1u) << t;
    EXPECT_EQ(count(t, "  tile-raster: 2 ms GPU\n"), 1u) << t;
    EXPECT_EQ(count(t, "  total: 2.5 ms GPU\n"), 1u) << t;
  }
  EXPECT_NE(ta.find("  backend: compute (the calibration's numbers); its memory 2000 bytes (4 per cell, 2 per pixel)\n"), std::string::npos) << ta;
  EXPECT_NE(tb.find("  volume: --mode interval-sorted, backend compute, ordering per-pixel [exact]; surfaces: --surface-mode forward with shadows"),
            std::string::npos) << tb;
}

// Surfaces alone: the backend's own counters beside the frame's, the default lighting said.
TEST(FrameStatsWriter, SurfaceStatsCarryTheBackendsCountersAndTheLighting) {
  mixed::FrameStats s;
  s.device = "a GPU";
  s.gpu = true;
  s.width = 16;
  s.height = 12;
  s.frames = 3;
  mixed::SurfaceStats f;
  f.scene = "cube";
  f.mode = "htex";
  f.triangles = 12;
  f.covered_pixels = 100;
  f.default_lighting = true;
  f.takes_frames = true;
  f.counts.shaded = 77;
  f.counts.shaded_field = "shaded_texels";
  f.counts.stats = {{"pool_pages", uint64_t(64)}, {"stretch_l2", 1.25}};
  s.surfaces = f;
  s.passes = {{"shading", 1.0}};
  const StatsJson js = frame_json(s, {.image = "c.png"});
  EXPECT_EQ(js["dataset"], "cube");
  EXPECT_EQ(js["mode"], "htex");
  EXPECT_EQ(js["shaded_texels"], 77u);
  EXPECT_EQ(js["pool_pages"], 64u);
  EXPECT_DOUBLE_EQ(js["stretch_l2"].get<double>(), 1.25);
  EXPECT_EQ(js["frames"], 3u);
  EXPECT_EQ(js["default_lighting"], true);
  EXPECT_FALSE(js.contains("supersample"));  // the backend takes none
  EXPECT_FALSE(js.contains("cpu_passes"));
  const std::string t = frame_text(s, {.image = "c.png"});
  EXPECT_NE(t.find("  covered: 100 pixels, 77 shading invocations\n"), std::string::npos) << t;
  EXPECT_NE(t.find("default key light (it casts shadows) and sky"), std::string::npos) << t;
}

// A path-traced frame: the path tracer's settings and guards, and nothing of a GPU frame's.
TEST(FrameStatsWriter, PathTracedStatsAreThePathTracersOwn) {
  mixed::FrameStats s;
  s.device = "CPU path tracer (double precision)";
  s.width = 8;
  s.height = 4;
  mixed::PathStats p;
  p.scene = "cornell-box";
  p.mode = "path-reference";
  p.settings.samples_per_pixel = 16;
  p.settings.max_bounces = 3;
  p.counts.rays = 999;
  p.counts.non_finite = 2;
  s.path = p;
  const StatsJson js = frame_json(s, {.image = "p.pfm"});
  EXPECT_EQ(js["samples_per_pixel"], 16u);
  EXPECT_EQ(js["rays"], 999u);
  EXPECT_EQ(js["non_finite"], 2u);
  EXPECT_FALSE(js.contains("passes"));
  const std::string t = frame_text(s, {.image = "p.pfm"});
  EXPECT_EQ(t.rfind("wrote p.pfm (8x4, cornell-box, 16 samples per pixel, at most 3 bounces) on the CPU path tracer in ", 0), 0u) << t;
  EXPECT_NE(t.find("  999 rays; guards: 0 zero-pdf samples, 2 non-finite samples"), std::string::npos) << t;
}

}  // namespace
}  // namespace prismoid::app
