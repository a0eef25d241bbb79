// The renderer facade (renderer/mixed/scene_renderer.hpp): what draws a frame follows from the scene
// and the modes' rows, and the facade adds nothing to the frame of the renderer it hands it to.
// Each frame is compared with the same frame drawn by that renderer directly, number for number
// (the compute backend and the surface backends are deterministic); their accuracy against the
// references is the other suites' business.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "mixed/square_scene.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

constexpr VkExtent2D kSize{24, 20};
const test::Square kSquare{0.2, -0.5, 0.5, -0.5, 0.5};

Camera camera() { return test::square_view(); }

TetMesh ball() { return make_ball_mesh(glm::dvec3(0.0), 1.0, 1, 2.0); }

mixed::SceneSettings volume_settings(const char* mode) {
  mixed::SceneSettings s;
  s.size = kSize;
  s.volume_mode = frame::find_volume_mode(mode);
  s.volume.backend = frame::IntervalBackend::Compute;
  s.volume.resolve.quantity = volume::Quantity::OpticalDepth;
  s.warm_up_seconds = 0.0;
  return s;
}

TEST(SceneRenderer, CpuModesOpenNoDevice) {
  const TetMesh mesh = ball();
  mixed::SceneRenderer volume({.volume = &mesh}, mixed::DeviceRequest{});
  const mixed::SceneSettings settings = volume_settings("reference");
  const mixed::SceneFrame f = volume.render(camera(), settings);
  EXPECT_FALSE(f.gpu);
  EXPECT_EQ(volume.instance(), nullptr);
  ASSERT_TRUE(f.volume.has_value());
  EXPECT_FALSE(f.timing.has_value());
  const frame::OffscreenFrame direct = volume::reference_backend().render(mesh, camera(), settings.volume.resolve, kSize, false);
  EXPECT_EQ(f.volume->quantity, direct.quantity);

  const SurfaceScene scene = test::square_scene(kSquare);
  mixed::SceneRenderer surfaces({.surfaces = &scene}, mixed::DeviceRequest{});
  mixed::SceneSettings path;
  path.size = kSize;
  path.surface_mode = surface::find_surface_mode("path-reference");
  path.path.samples_per_pixel = 1;
  const mixed::SceneFrame p = surfaces.render(camera(), path);
  EXPECT_FALSE(p.gpu);
  EXPECT_EQ(surfaces.instance(), nullptr);
  ASSERT_TRUE(p.path.has_value());
  EXPECT_EQ(p.path->width, kSize.width);
  EXPECT_EQ(p.path->height, kSize.height);
  EXPECT_THROW(surfaces.reference(camera(), path, p), std::logic_error);
}

class SceneRendererGpu : public test::GpuTest {};

TEST_F(SceneRendererGpu, AVolumeFrameIsTheFrameRenderersOwnTimedAsAsked) {
  const TetMesh mesh = ball();
  mixed::SceneRenderer facade({.volume = &mesh}, device());
  mixed::SceneSettings settings = volume_settings("interval-sorted");
  settings.frames = 3;
  const mixed::SceneFrame f = facade.render(camera(), settings);
  ASSERT_TRUE(f.gpu);
  ASSERT_TRUE(f.volume.has_value());
  ASSERT_TRUE(f.timing.has_value());
  EXPECT_EQ(f.timing->frames, 3u);
  EXPECT_EQ(f.frame_cpu_ms.size(), 3u);  // the timed frames' CPU time, the warm-up's left out
  ASSERT_EQ(f.timing->passes.size(), f.volume->passes.size());
  for (size_t i = 0; i < f.volume->passes.size(); ++i) EXPECT_EQ(f.timing->passes[i].name, f.volume->passes[i].name);
  EXPECT_EQ(f.device, device().capabilities().name);
  // Its typed stats are the frame's own.
  ASSERT_TRUE(f.stats.volume.has_value());
  EXPECT_EQ(f.stats.frames, 3u);
  EXPECT_EQ(f.stats.volume->cells, mesh.tets.size());
  EXPECT_EQ(f.stats.volume->report.pairs, f.volume->report.pairs);
  EXPECT_EQ(f.stats.volume->report.backend, "compute");
  EXPECT_EQ(f.stats.passes.size(), f.volume->passes.size());
  EXPECT_EQ(f.stats.plan->gpu_pass_names(), f.volume->report.plan.gpu_pass_names());
  EXPECT_FALSE(f.stats.surfaces.has_value());
  mixed::SceneSettings none = settings;
  none.frames = 0;
  EXPECT_THROW(facade.render(camera(), none), InputError);

  frame::FrameRenderer direct(device(), mesh);
  const frame::OffscreenFrame d = direct.render_offscreen(camera(), settings.volume, kSize);
  EXPECT_EQ(f.volume->quantity, d.quantity);
  // Its reference is the cpu backend's frame of the same settings.
  const mixed::SceneFrame r = facade.reference(camera(), settings, f);
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_EQ(r.volume->quantity, volume::reference_backend().render(mesh, camera(), settings.volume.resolve, kSize, false).quantity);
}

// An interactive frame is drawn once and keeps what a still camera lets the next frame reuse: the
// second frame of a still camera skips the exact order and draws the same image; a timed frame
// forgets it (each costs what a moving camera's does).
TEST_F(SceneRendererGpu, AnInteractiveFrameReusesWhatAStillCameraKeeps) {
  TetMesh mesh = ball();
  for (const glm::dvec3& p : mesh.points) mesh.point_scalars.push_back(0.5 + 0.5 * p.x);  // colour through the transfer function
  mixed::SceneRenderer facade({.volume = &mesh}, device());
  mixed::SceneSettings settings = volume_settings("interval-exact-order");
  settings.volume.backend = frame::IntervalBackend::Mesh;
  settings.volume.ordering = frame::Ordering::Exact;
  settings.volume.resolve.quantity = volume::Quantity::Color;  // the order matters only for colour
  settings.interactive = true;
  settings.frames = 0;  // unused by an interactive frame
  const auto ran = [](const frame::OffscreenFrame& f, const char* pass) { return f.report.plan.has(pass); };
  const mixed::SceneFrame first = facade.render(camera(), settings);
  ASSERT_TRUE(first.volume.has_value());
  EXPECT_FALSE(first.timing.has_value());
  EXPECT_TRUE(ran(*first.volume, "exact-order"));
  const mixed::SceneFrame still = facade.render(camera(), settings);
  EXPECT_FALSE(ran(*still.volume, "exact-order"));
  EXPECT_TRUE(still.volume->report.plan.reuses_order);
  EXPECT_EQ(still.volume->emission, first.volume->emission);
  settings.interactive = false;
  settings.frames = 1;
  const mixed::SceneFrame timed = facade.render(camera(), settings);
  ASSERT_TRUE(timed.timing.has_value());
  EXPECT_TRUE(ran(*timed.volume, "exact-order"));
  EXPECT_EQ(timed.volume->emission, first.volume->emission);
}

// A time series on a static mesh (issue "Simulations as they come"): the steps after the first send
// only their fields to the GPU, counted, and each step's image is the one a renderer made for that
// step alone draws, number for number, on both GPU backends; a still camera keeps its exact order
// across steps (the order depends on the geometry alone). Another geometry is uploaded whole.
TEST_F(SceneRendererGpu, AStaticMeshSeriesUploadsItsMeshOnce) {
  std::vector<TetMesh> steps;
  for (const double w : {1.0, -1.0, 0.5}) {
    TetMesh step = ball();
    for (double& sigma : step.cell_extinction) sigma *= 1.0 + w;  // 2, 0 and 1.5 times
    for (const glm::dvec3& p : step.points) step.point_scalars.push_back(0.5 + 0.5 * w * p.x);
    steps.push_back(std::move(step));
  }
  const auto ran = [](const frame::OffscreenFrame& f, const char* pass) { return f.report.plan.has(pass); };
  for (const frame::IntervalBackend backend : {frame::IntervalBackend::Mesh, frame::IntervalBackend::Compute}) {
    SCOPED_TRACE(backend == frame::IntervalBackend::Mesh ? "mesh" : "compute");
    mixed::SceneSettings settings = volume_settings("interval-exact-order");
    settings.volume.backend = backend;
    settings.volume.ordering = frame::Ordering::Exact;
    settings.volume.resolve.quantity = volume::Quantity::Color;
    settings.interactive = true;
    mixed::SceneRenderer series({.volume = &steps[0]}, device());
    for (size_t i = 0; i < steps.size(); ++i) {
      if (i > 0) series.set_volume(steps[i]);
      const mixed::SceneFrame f = series.render(camera(), settings);
      ASSERT_TRUE(f.volume.has_value());
      EXPECT_EQ(series.volume_uploads().meshes, 1u) << "step " << i;
      EXPECT_EQ(series.volume_uploads().fields, i) << "step " << i;
      if (backend == frame::IntervalBackend::Mesh) {
        EXPECT_EQ(ran(*f.volume, "exact-order"), i == 0) << "step " << i;
      }
      mixed::SceneRenderer alone({.volume = &steps[i]}, device());
      const mixed::SceneFrame a = alone.render(camera(), settings);
      EXPECT_EQ(f.volume->emission, a.volume->emission) << "step " << i;
      EXPECT_EQ(f.volume->quantity, a.volume->quantity) << "step " << i;
    }
    // The steps differ: the test would not see a field left from the step before.
    EXPECT_NE(series.render(camera(), settings).volume->emission,
              mixed::SceneRenderer({.volume = &steps[0]}, device()).render(camera(), settings).volume->emission);
    // A step whose fields are refused: neither this call nor the next frame draws the step before.
    TetMesh bad = steps[0];
    bad.point_scalars.pop_back();  // one value short
    EXPECT_THROW(series.set_volume(bad), InputError);
    EXPECT_THROW(series.render(camera(), settings), InputError);
    TetMesh finer = make_ball_mesh(glm::dvec3(0.0), 1.0, 2, 2.0);
    for (const glm::dvec3& p : finer.points) finer.point_scalars.push_back(0.5 + 0.5 * p.x);
    series.set_volume(finer);
    const mixed::SceneFrame f = series.render(camera(), settings);
    EXPECT_EQ(series.volume_uploads().meshes, 2u);
    EXPECT_EQ(f.stats.volume->cells, finer.tets.size());
  }
}

// The automatic backend is the front end's hook's choice, and never silently the default.
TEST_F(SceneRendererGpu, AnAutomaticBackendIsTheHooksChoice) {
  const TetMesh mesh = ball();
  mixed::SceneSettings settings = volume_settings("interval-sorted");
  settings.volume.backend = frame::IntervalBackend::Mesh;
  settings.volume_backend_auto = true;
  mixed::SceneRenderer without({.volume = &mesh}, device());
  EXPECT_THROW(without.render(camera(), settings), std::invalid_argument);
  mixed::SceneRenderer with({.volume = &mesh}, device(), [](frame::FrameSettings& s, const vk::Device&) {
    s.backend = frame::IntervalBackend::Compute;
    s.backend_reason = "the test's choice";
  });
  const mixed::SceneFrame f = with.render(camera(), settings);
  EXPECT_EQ(f.volume_settings.backend_reason, "the test's choice");
  EXPECT_EQ(f.volume->report.backend, "compute");
}

TEST_F(SceneRendererGpu, SurfaceAndMixedFramesAreTheirRenderersOwn) {
  const SurfaceScene scene = test::square_scene(kSquare);
  mixed::SceneRenderer surfaces({.surfaces = &scene}, device());
  mixed::SceneSettings s;
  s.size = kSize;
  s.surface_mode = surface::find_surface_mode("forward");
  s.shadows = false;
  const mixed::SceneFrame f = surfaces.render(camera(), s);
  ASSERT_TRUE(f.surfaces.has_value());
  surface::SurfaceRenderer direct(device(), scene);
  direct.set_shadows(false);
  EXPECT_EQ(f.surfaces->rgba, direct.render_offscreen(camera(), "forward", kSize).rgba);
  ASSERT_TRUE(f.stats.surfaces.has_value());
  uint64_t covered = 0;
  for (size_t i = 3; i < f.surfaces->rgba.size(); i += 4) covered += f.surfaces->rgba[i] == 1.0f;
  EXPECT_GT(covered, 0u);
  EXPECT_EQ(f.stats.surfaces->covered_pixels, covered);
  EXPECT_EQ(f.stats.surfaces->triangles, scene.meshes.front().triangles.size());
  EXPECT_FALSE(f.stats.surfaces->shadows);

  const TetMesh mesh = ball();
  mixed::SceneRenderer both({.volume = &mesh, .surfaces = &scene}, device());
  mixed::SceneSettings m = volume_settings("interval-sorted");
  m.surface_mode = s.surface_mode;
  m.shadows = false;
  const mixed::SceneFrame g = both.render(camera(), m);
  ASSERT_TRUE(g.mixed.has_value());
  EXPECT_FALSE(g.volume.has_value());
  mixed::MixedRenderer mixed_direct(device(), mesh, scene);
  mixed_direct.surface_renderer().set_shadows(false);
  EXPECT_EQ(g.mixed->display, mixed_direct.render(camera(), m.volume, kSize, "forward").display);
  ASSERT_TRUE(g.stats.volume.has_value() && g.stats.mixed.has_value());
  EXPECT_EQ(g.stats.mixed->mode, "forward");
  EXPECT_TRUE(g.stats.mixed_plan.has_value());
  EXPECT_EQ(g.stats.cpu_passes.size(), g.mixed->cpu_passes.size());
}

// The bench's sequences: timed frames read nothing back and the image is the last timed frame's,
// at the camera path's last camera where the camera moves; every timed frame's shading is counted.
TEST_F(SceneRendererGpu, ASurfaceSequenceEndsAtItsLastCamera) {
  const SurfaceScene scene = test::square_scene(kSquare);
  mixed::SceneRenderer facade({.surfaces = &scene}, device());
  EXPECT_FALSE(facade.surface_renderer().modes().empty());
  mixed::SceneSettings s;
  s.size = kSize;
  s.surface_mode = surface::find_surface_mode("forward");
  s.shadows = false;
  s.frames = 2;
  s.warm_up_seconds = 0.0;
  const Camera start = camera();
  Camera last = start;
  last.eye += glm::dvec3(0.3, 0.1, 0.0);
  // Four cameras: two untimed, two timed; the last is `last`.
  s.sequence = mixed::SurfaceSequence{.camera_path = [&](uint32_t i) { return i == 3 ? last : start; }};
  const mixed::SceneFrame f = facade.render(start, s);
  ASSERT_TRUE(f.surfaces.has_value());
  ASSERT_TRUE(f.timing.has_value());
  EXPECT_EQ(f.timing->frames, 2u);
  ASSERT_EQ(f.frame_shaded.size(), 2u);
  EXPECT_GT(f.frame_shaded.back(), 0u);
  surface::SurfaceRenderer direct(device(), scene);
  direct.set_shadows(false);
  const surface::SurfaceRenderer::Offscreen moved = direct.render_offscreen(last, "forward", kSize);
  EXPECT_EQ(f.surfaces->rgba, moved.rgba);
  EXPECT_NE(moved.rgba, direct.render_offscreen(start, "forward", kSize).rgba);  // the path's end is what shows
  EXPECT_EQ(f.stats.surfaces->covered_pixels, [&] {
    uint64_t n = 0;
    for (size_t i = 3; i < moved.rgba.size(); i += 4) n += moved.rgba[i] == 1.0f;
    return n;
  }());
}

}  // namespace
}  // namespace prismoid
