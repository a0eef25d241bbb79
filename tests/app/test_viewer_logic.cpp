// The viewer's logic that needs no window: scripts, opacity-point edits, mode and quantity
// rules of the view state.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstdio>
#include <string>
#include <vector>

#include "app/viewer/interactive_scale.hpp"
#include "app/viewer/compare.hpp"
#include "app/viewer/tf_edit.hpp"
#include "app/viewer/view_state.hpp"
#include "app/viewer/viewer_script.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {
namespace {

TEST(ViewerScript, FramesAccumulateAndCommandsKeepTheirArguments) {
  const auto script = app::parse_script(
      "# a comment\n"
      "frame 5\n"
      "mode interval-sorted   # trailing comment\n"
      "camera --eye 1,2,3 --target 0,0,0\n"
      "wait 10\n"
      "screenshot out/a.png\n"
      "frame 40\n"
      "close\n",
      "test.script");
  ASSERT_EQ(script.size(), 4u);
  EXPECT_EQ(script[0].frame, 5u);
  EXPECT_EQ(script[0].verb, "mode");
  EXPECT_EQ(script[0].args, std::vector<std::string>{"interval-sorted"});
  EXPECT_EQ(script[1].frame, 5u);
  EXPECT_EQ(script[1].rest, " --eye 1,2,3 --target 0,0,0");
  EXPECT_EQ(script[2].frame, 15u);
  EXPECT_EQ(script[2].where, "test.script:6");
  EXPECT_EQ(script[3].frame, 40u);
}

TEST(ViewerScript, UnknownCommandsAndWrongArgumentCountsNameTheLine) {
  try {
    app::parse_script("frame 1\nfrobnicate 3\n", "s.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "s.txt:2");
  }
  EXPECT_THROW(app::parse_script("resize 100\n", "s"), InputError);
  EXPECT_THROW(app::parse_script("frame x\n", "s"), InputError);
}

// Paths with spaces are quoted as in a shell (`open my data.vtu` opened "my"); a # inside quotes
// is part of the word; an unclosed quote names its line and column.
TEST(ViewerScript, QuotedWordsKeepTheirSpaces) {
  const auto script = app::parse_script("open \"my data.vtu\" 'the array'  # comment\n"
                                        "screenshot \"shots/#1 \\\"best\\\".png\"\n",
                                        "s");
  ASSERT_EQ(script.size(), 2u);
  EXPECT_EQ(script[0].args, (std::vector<std::string>{"my data.vtu", "the array"}));
  EXPECT_EQ(script[1].args, std::vector<std::string>{"shots/#1 \"best\".png"});
  try {
    app::parse_script("frame 1\nopen \"my data.vtu\n", "s.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "s.txt:2");
    EXPECT_NE(std::string(e.what()).find("column 6 is not closed"), std::string::npos) << e.what();
  }
}

// Frame numbers stop at 10^8: 4294967295 wrapped round the window's counter and ran at frame 1.
TEST(ViewerScript, FramesBeyondTheLastAreRefusedNotWrapped) {
  for (const char* text : {"frame 4294967295\nclose\n", "frame 100000000\nwait 1\nclose\n", "frame 99999999999999999999\n"}) {
    try {
      app::parse_script(text, "s");
      ADD_FAILURE() << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source().rfind("s:", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(app::parse_script("frame 100000000\nclose\n", "s").front().frame, 100000000u);
}

// What is not a small regular file is refused before anything is read (`--script /dev/zero`
// grew memory until bad_alloc; a FIFO would wait for a writer).
TEST(ViewerScript, WhatIsNotAScriptFileIsRefusedBeforeReading) {
  const std::string fifo = ::testing::TempDir() + "script-fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {std::string("/dev/zero"), fifo, ::testing::TempDir()}) {
    try {
      app::read_script(path);
      ADD_FAILURE() << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), path);
      EXPECT_NE(std::string(e.what()).find("not"), std::string::npos) << e.what();
    }
  }
  std::remove(fifo.c_str());
  const std::string big = ::testing::TempDir() + "big-script";
  {
    std::FILE* f = std::fopen(big.c_str(), "w");
    ASSERT_NE(f, nullptr);
    for (int i = 0; i < 100000; ++i) std::fputs("# a comment line\n", f);
    std::fclose(f);
  }
  try {
    app::read_script(big);
    ADD_FAILURE() << "a 1.7 MB script was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at most 1048576"), std::string::npos) << e.what();
  }
  std::remove(big.c_str());
}

TEST(TfEdit, OpacityPointsStaySortedInsideTheUnitSquare) {
  volume::TransferFunction tf = volume::preset("viridis");
  const size_t before = tf.opacity.size();
  const size_t i = app::add_opacity_point(tf, 0.3, 1.7);
  EXPECT_EQ(tf.opacity.size(), before + 1);
  EXPECT_DOUBLE_EQ(tf.opacity[i].opacity, 1.0);
  app::move_opacity_point(tf, i, 5.0, -1.0);  // dragged far right and below: stops at its neighbour
  for (size_t k = 0; k + 1 < tf.opacity.size(); ++k) EXPECT_LE(tf.opacity[k].x, tf.opacity[k + 1].x);
  EXPECT_DOUBLE_EQ(tf.opacity[i].opacity, 0.0);
  EXPECT_EQ(app::nearest_opacity_point(tf, tf.opacity[i].x, 0.01, 0.05), i);
  EXPECT_EQ(app::nearest_opacity_point(tf, 0.5, 0.5, 1e-6), tf.opacity.size());
  while (tf.opacity.size() > 1) ASSERT_TRUE(app::remove_opacity_point(tf, 0));
  EXPECT_FALSE(app::remove_opacity_point(tf, 0)) << "the last point must stay";
  EXPECT_NO_THROW(volume::validate(tf));
}

TEST(ViewState, MarchModesOnlyForFieldsAndQuantitiesFollowTheMode) {
  app::ViewState state;
  state.datasets.push_back(app::make_dataset(make_default_volume()));
  EXPECT_EQ(app::modes_for(state.dataset()).size(), 3u);
  EXPECT_FALSE(app::set_mode(state, "interval-march").empty());
  EXPECT_TRUE(app::set_mode(state, "interval-exact-order").empty());
  EXPECT_EQ(state.settings.ordering, frame::Ordering::Exact);
  EXPECT_FALSE(app::set_quantity(state, volume::Quantity::Isosurface).empty());
  // Shared vertices fix the draw order: refused for colour in a sorted mode, fine in mesh order.
  state.settings.resolve.shared_vertices = true;
  ASSERT_TRUE(state.dataset().has_scalars);
  EXPECT_TRUE(app::set_quantity(state, volume::Quantity::Color).empty());
  EXPECT_FALSE(state.settings.resolve.shared_vertices);
  EXPECT_TRUE(app::set_mode(state, "interval").empty());
  EXPECT_TRUE(app::shared_vertices_problem(state).empty());

  app::ViewState field;
  field.datasets.push_back(app::make_dataset(volume::make_field_mesh(volume::field_from_name("marschner-lobb"), 4, 1.0),
                                             volume::field_from_name("marschner-lobb")));
  EXPECT_TRUE(app::set_mode(field, "interval-march").empty());
  EXPECT_TRUE(field.settings.resolve.march.enabled);
  EXPECT_GT(field.settings.resolve.march.step, 0.0);
  EXPECT_TRUE(app::set_quantity(field, volume::Quantity::Isosurface).empty());
  EXPECT_TRUE(app::set_mode(field, "interval-sorted").empty());
  EXPECT_FALSE(field.settings.resolve.march.enabled);
  EXPECT_NE(field.settings.resolve.quantity, volume::Quantity::Isosurface) << "interval-sorted cannot show an isosurface";
}

TEST(ViewState, PresetsKeepTheRangeAndDensity) {
  app::ViewState state;
  state.datasets.push_back(app::make_dataset(make_default_volume()));
  state.settings.resolve.transfer.range_lo = -2.0;
  state.settings.resolve.transfer.range_hi = 7.0;
  state.settings.resolve.transfer.density_scale = 3.0;
  EXPECT_TRUE(app::set_preset(state, "black-body").empty());
  EXPECT_EQ(state.settings.resolve.transfer.name, "black-body");
  EXPECT_DOUBLE_EQ(state.settings.resolve.transfer.range_lo, -2.0);
  EXPECT_DOUBLE_EQ(state.settings.resolve.transfer.range_hi, 7.0);
  EXPECT_DOUBLE_EQ(state.settings.resolve.transfer.density_scale, 3.0);
  EXPECT_FALSE(app::set_preset(state, "rainbow").empty());
}

// Split view's B goes through A's rules (refused modes leave it unchanged), keeps its own
// ordering, quantity and pre-integration size, and follows A's transfer function.
TEST(Compare, SplitViewsBFollowsAExceptInWhatBChose) {
  app::ViewState state;
  state.datasets.push_back(app::make_dataset(make_default_volume()));
  ASSERT_TRUE(app::set_mode(state, "interval-sorted").empty());
  ASSERT_TRUE(app::set_quantity(state, volume::Quantity::Color).empty());
  EXPECT_TRUE(app::set_compare(state, app::CompareMode::Split).empty());
  EXPECT_EQ(state.compare, app::CompareMode::Split);
  EXPECT_EQ(state.compare_mode, "interval-exact-order");  // the default B differs from A
  EXPECT_FALSE(app::set_compare_mode(state, "interval-march").empty());
  EXPECT_EQ(state.compare_mode, "interval-exact-order");
  EXPECT_TRUE(app::set_compare_quantity(state, volume::Quantity::Transmittance).empty());
  EXPECT_FALSE(app::set_compare_quantity(state, volume::Quantity::Isosurface).empty());
  state.compare_settings.resolve.preintegration_size = 16;
  state.settings.resolve.transfer.density_scale = 7.0;
  state.settings.resolve.tetlet_size = 4;
  const frame::FrameSettings b = app::compare_frame_settings(state);
  EXPECT_EQ(b.ordering, frame::Ordering::Exact);
  EXPECT_EQ(b.resolve.quantity, volume::Quantity::Transmittance);
  EXPECT_EQ(b.resolve.preintegration_size, 16u);
  EXPECT_EQ(b.resolve.transfer.density_scale, 7.0);
  EXPECT_EQ(b.resolve.tetlet_size, 4u);
  EXPECT_EQ(state.settings.ordering, frame::Ordering::GpuSort) << "A is untouched by B's choices";
  EXPECT_EQ(state.settings.resolve.quantity, volume::Quantity::Color);
  EXPECT_EQ(app::compare_mode_of_name("difference"), app::CompareMode::Difference);
  EXPECT_FALSE(app::compare_mode_of_name("both").has_value());
}

// The split view compares the two interval backends: B on compute, A on mesh shaders, each
// frame's settings carrying its own; tetlets (the mesh backend's) never reach a compute frame.
TEST(Compare, BackendsAreSwitchedAndComparedSideBySide) {
  app::ViewState state;
  state.datasets.push_back(app::make_dataset(make_default_volume()));
  ASSERT_TRUE(app::set_mode(state, "interval-sorted").empty());
  EXPECT_EQ(state.settings.backend, frame::IntervalBackend::Mesh);
  EXPECT_FALSE(app::set_backend(state, "gpu").empty());
  EXPECT_EQ(state.settings.backend, frame::IntervalBackend::Mesh) << "an unknown name changes nothing";
  EXPECT_TRUE(app::set_compare_backend(state, "compute").empty());
  EXPECT_TRUE(app::set_compare(state, app::CompareMode::Split).empty());
  EXPECT_EQ(state.compare_mode, "interval-sorted") << "B chose only its backend: A's mode";
  state.settings.resolve.shared_vertices = true;
  frame::FrameSettings b = app::compare_frame_settings(state);
  EXPECT_EQ(b.backend, frame::IntervalBackend::Compute);
  EXPECT_FALSE(b.resolve.shared_vertices);
  EXPECT_EQ(state.settings.backend, frame::IntervalBackend::Mesh) << "A is untouched by B's backend";
  const std::string said = app::set_backend(state, "compute");
  EXPECT_NE(said.find("shared vertices"), std::string::npos) << said;
  EXPECT_EQ(state.settings.backend, frame::IntervalBackend::Compute);
  EXPECT_FALSE(state.settings.resolve.shared_vertices);
  EXPECT_TRUE(app::set_compare_backend(state, "mesh").empty());
  b = app::compare_frame_settings(state);
  EXPECT_EQ(b.backend, frame::IntervalBackend::Mesh);
}

TEST(Compare, ReferenceSizeKeepsTheAspectAndTheKeySeesEveryChange) {
  EXPECT_EQ(app::reference_size({320, 240}, 512).width, 320u);
  const VkExtent2D r = app::reference_size({1280, 720}, 512);
  EXPECT_EQ(r.width, 512u);
  EXPECT_EQ(r.height, 288u);
  EXPECT_EQ(app::reference_size({300, 2000}, 512).height, 512u);
  const Camera c;
  const frame::FrameSettings s;
  const std::string key = app::reference_key(c, s, {64, 48}, 0);
  EXPECT_EQ(key, app::reference_key(c, s, {64, 48}, 0));
  Camera moved = c;
  moved.eye.x += 1e-12;  // a camera at rest is one whose key does not change at all
  EXPECT_NE(key, app::reference_key(moved, s, {64, 48}, 0));
  frame::FrameSettings other = s;
  other.resolve.transfer.opacity.back().opacity *= 0.5;
  EXPECT_NE(key, app::reference_key(c, other, {64, 48}, 0));
  EXPECT_NE(key, app::reference_key(c, s, {64, 49}, 0));
  EXPECT_NE(key, app::reference_key(c, s, {64, 48}, 1));
}

}  // namespace
}  // namespace prismoid

namespace prismoid {
namespace {

// The window's resolution while the camera moves (app/viewer/interactive_scale.hpp): a frame too
// slow for the target halves the resolution, step by step; a still camera gets full resolution
// at once; the next motion starts where the last ended; fast frames keep full resolution.
TEST(InteractiveScale, HoldsTheTargetWhileMovingAndRefinesWhenStill) {
  app::InteractiveScale s(100.0);
  const VkExtent2D window{1280, 800};
  s.update(true, 0.0, 0);  // first frame: nothing measured yet
  EXPECT_EQ(s.level(), 0u);
  // Full resolution takes 1400 ms: coarser one level per measured frame, until one holds.
  const double ms_at[4] = {1400.0, 380.0, 95.0, 30.0};
  uint32_t frames = 0;
  while (frames < 20) {
    const uint32_t drawn = s.level();
    s.update(true, ms_at[drawn], drawn);
    ++frames;
    if (s.level() == drawn && ms_at[drawn] <= 100.0) break;
  }
  EXPECT_EQ(s.level(), 2u);  // 95 ms at 1/4 per side holds 100 ms; 1/2 did not
  EXPECT_EQ(s.extent(window).width, 320u);
  EXPECT_EQ(s.extent(window).height, 200u);
  // It stays there: the finer level's measured 380 ms would miss the target.
  for (int i = 0; i < 5; ++i) s.update(true, ms_at[s.level()], s.level());
  EXPECT_EQ(s.level(), 2u);
  EXPECT_TRUE(s.moving());
  // The camera stops: the next frame is full resolution.
  s.update(false, ms_at[2], 2);
  EXPECT_EQ(s.level(), 0u);
  EXPECT_EQ(s.extent(window).width, 1280u);
  EXPECT_FALSE(s.moving());
  // It moves again: straight back to 1/4, not through the slow levels.
  s.update(true, ms_at[0], 0);
  EXPECT_EQ(s.level(), 2u);
  // Where full resolution holds the target, moving changes nothing.
  app::InteractiveScale fast(100.0);
  for (int i = 0; i < 10; ++i) fast.update(true, 12.0, fast.level());
  EXPECT_EQ(fast.level(), 0u);
  // Never coarser than 1/8, and never an empty image.
  app::InteractiveScale slow(100.0);
  for (int i = 0; i < 20; ++i) slow.update(true, 5000.0, slow.level());
  EXPECT_EQ(slow.level(), app::InteractiveScale::kCoarsest);
  EXPECT_EQ(slow.extent({5, 3}).width, 1u);
  EXPECT_EQ(slow.extent({5, 3}).height, 1u);
  // With coarse proxies of the data on offer, two steps further: the proxies, still at 1/8.
  slow.allow_proxy(true);
  slow.update(true, 500.0, slow.level());
  EXPECT_EQ(slow.level(), app::InteractiveScale::kProxy);
  EXPECT_EQ(slow.proxy_index(), 0u);
  for (int i = 0; i < 4; ++i) slow.update(true, 500.0, slow.level());
  EXPECT_EQ(slow.level(), app::InteractiveScale::kCoarsestProxy);
  EXPECT_EQ(slow.proxy_index(), 1u);
  EXPECT_TRUE(slow.proxy());
  EXPECT_EQ(slow.extent(window).width, 160u);
  slow.update(true, 60.0, slow.level());  // the proxy holds the target: it stays
  EXPECT_TRUE(slow.proxy());
  slow.update(false, 60.0, slow.level());  // still: the data itself, full resolution
  EXPECT_EQ(slow.level(), 0u);
  EXPECT_FALSE(slow.proxy());
}

}  // namespace
}  // namespace prismoid
