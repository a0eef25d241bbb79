// The surface renderer (renderer/surface/surface_renderer) on the GPU: every mode of the mode
// table records exactly the passes the planner gives its frame (the passes its backend lists by
// role, shadow rays only with shadows, GI passes only for GI modes with light to bounce), and a
// frame the plan leaves without GI or shadows is recorded without them.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "renderer/surface/surface_modes.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/vk/memory.hpp"
#include "scene/surface_generators.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid::test {
namespace {

class SurfaceRendererTest : public GpuTest {};

// The timed passes of one recorded frame.
std::vector<std::string> record_frame(surface::SurfaceRenderer& renderer, const Camera& camera, const std::string& mode) {
  vk::GpuTimer timer(renderer.device(), 16);
  timer.submit_and_wait([&](VkCommandBuffer cmd) { renderer.record(cmd, camera, mode, timer); });
  return timer.recorded();
}

std::vector<float> read_display(const surface::SurfaceRenderer& renderer) {
  std::vector<float> rgba(size_t(renderer.extent().width) * renderer.extent().height * 4);
  vk::read_image(renderer.device(), renderer.display(), sizeof(float) * 4, std::as_writable_bytes(std::span(rgba)));
  return rgba;
}

// What the mode's backend lists by role, in order, for a frame with or without GI.
std::vector<std::string> backend_passes(const surface::SurfaceMode& mode, bool gi) {
  const frame::SurfacePasses& p = mode.backend->passes;
  std::vector<std::string> names;
  for (const frame::SurfaceStep* step : {&p.pre_z, &p.allocation, &p.shading})
    if (!step->name.empty()) names.push_back(step->name);
  if (gi)
    for (const frame::SurfaceStep& step : p.gi) names.push_back(step.name);
  if (!p.display.name.empty()) names.push_back(p.display.name);
  return names;
}

TEST_F(SurfaceRendererTest, EveryModeRecordsExactlyThePassesOfItsPlan) {
  const SurfaceScene box = make_cornell_box();
  const SurfaceScene scene = with_default_lighting(box, box.camera);
  surface::SurfaceRenderer renderer(device(), scene);
  renderer.resize({32, 24});
  ASSERT_FALSE(renderer.modes().empty());
  std::vector<bool> shadow_settings{false};
  if (renderer.can_shadow()) shadow_settings.push_back(true);
  size_t frames = 0;
  for (const bool shadows : shadow_settings)
    for (const std::string& name : renderer.modes()) {
      const surface::SurfaceMode& mode = *surface::find_surface_mode(name);
      renderer.set_shadows(shadows);
      const frame::FramePlan plan = renderer.plan(name);
      const std::vector<std::string> timed = record_frame(renderer, scene.camera, name);
      const std::string what = name + (shadows ? " with shadows" : " without shadows");
      EXPECT_EQ(timed, plan.gpu_pass_names()) << what;
      EXPECT_EQ(renderer.last_plan().gpu_pass_names(), plan.gpu_pass_names()) << what;
      // The plan is the backend's passes by role; GI only for the GI modes (the box has lights).
      EXPECT_EQ(plan.gpu_pass_names(), backend_passes(mode, mode.gi != frame::SurfaceGi::None)) << what;
      EXPECT_EQ(plan.find(frame::PassId::ShadowRays) != nullptr, shadows) << what;
      EXPECT_EQ(plan.find(frame::PassId::GlobalIllumination) != nullptr, mode.gi != frame::SurfaceGi::None) << what;
      for (const frame::PlannedPass& p : plan.passes) EXPECT_FALSE(p.reason.empty()) << what << ": " << p.name;
      // Something was drawn: finite radiance, and the box covers most of the image.
      const std::vector<float> rgba = read_display(renderer);
      size_t covered = 0;
      for (size_t i = 0; i < rgba.size(); i += 4) {
        for (int c = 0; c < 4; ++c) ASSERT_TRUE(std::isfinite(rgba[i + c])) << what;
        covered += rgba[i + 3] == 1.0f;
      }
      EXPECT_GT(covered, rgba.size() / 8) << what;
      ++frames;
    }
  EXPECT_EQ(frames, renderer.modes().size() * shadow_settings.size());
}

// Reuse where a mode's shading space is made from the whole view: FastAtlas's atlas is the same
// bit for bit while nothing changes, so such a frame shades nothing and shows the same image; its
// atlas and the meshlet atlas's per-frame charts (MSA-P, MSA-O) change when the camera turns,
// even with the eye where it was (a still eye, which keeps static charts' shading), so that
// frame shades again.
TEST_F(SurfaceRendererTest, PerFrameAtlasesReuseShadingOnlyForTheSameView) {
  const SurfaceScene box = make_cornell_box();
  const SurfaceScene scene = with_default_lighting(box, box.camera);
  surface::SurfaceRenderer renderer(device(), scene);
  renderer.resize({32, 24});
  renderer.set_shadows(false);
  Camera turned = scene.camera;
  turned.target += glm::dvec3(0.05, 0.0, 0.0);  // the eye stays
  record_frame(renderer, scene.camera, "fastatlas");
  ASSERT_GT(renderer.read_counts().shaded, 0u);
  const std::vector<float> first = read_display(renderer);
  record_frame(renderer, scene.camera, "fastatlas");
  EXPECT_EQ(renderer.read_counts().shaded, 0u);
  EXPECT_EQ(read_display(renderer), first);
  record_frame(renderer, turned, "fastatlas");
  EXPECT_GT(renderer.read_counts().shaded, 0u) << "the view turned: a new atlas";
  for (const msa::Parametrization charts : {msa::Parametrization::Perspective, msa::Parametrization::Orthographic}) {
    renderer.set_msa_charts(charts);
    record_frame(renderer, scene.camera, "msa");
    ASSERT_GT(renderer.read_counts().shaded, 0u) << msa::parametrization_name(charts);
    record_frame(renderer, scene.camera, "msa");
    EXPECT_EQ(renderer.read_counts().shaded, 0u) << msa::parametrization_name(charts);
    record_frame(renderer, turned, "msa");
    EXPECT_GT(renderer.read_counts().shaded, 0u) << msa::parametrization_name(charts) << ": the view turned";
  }
  renderer.set_msa_charts(msa::Parametrization::Projection);
  record_frame(renderer, scene.camera, "msa");
  record_frame(renderer, turned, "msa");
  EXPECT_EQ(renderer.read_counts().shaded, 0u) << "static charts: a still eye keeps every block's shading";
}

// A scene nothing lights (no lights, no emitters, a black sky): the planner leaves out the
// shadow rays and a GI mode's GI passes, the backend records the frame without them, and every
// covered pixel is black (no sky term, no light, no stale indirect radiance).
TEST_F(SurfaceRendererTest, AFrameWithNothingToLightRecordsNeitherShadowRaysNorGi) {
  SurfaceScene dark = make_cornell_box();
  for (SurfaceMaterial& m : dark.materials) m.emission = glm::dvec3(0.0);
  dark.point_lights.clear();
  dark.directional_lights.clear();
  dark.sky = Sky{};
  ASSERT_FALSE(has_light(dark));
  surface::SurfaceRenderer renderer(device(), dark);
  renderer.resize({32, 24});
  for (const std::string& name : renderer.modes()) {
    const surface::SurfaceMode& mode = *surface::find_surface_mode(name);
    const std::vector<std::string> timed = record_frame(renderer, dark.camera, name);
    const frame::FramePlan& plan = renderer.last_plan();
    EXPECT_EQ(timed, plan.gpu_pass_names()) << name;
    EXPECT_EQ(timed, backend_passes(mode, false)) << name;
    EXPECT_EQ(plan.find(frame::PassId::ShadowRays), nullptr) << name;
    EXPECT_EQ(plan.find(frame::PassId::GlobalIllumination), nullptr) << name;
    const std::vector<float> rgba = read_display(renderer);
    size_t covered = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) {
      if (rgba[i + 3] != 1.0f) continue;
      ++covered;
      for (int c = 0; c < 3; ++c) ASSERT_EQ(rgba[i + c], 0.0f) << name << " pixel " << i / 4;
    }
    EXPECT_GT(covered, rgba.size() / 8) << name;
  }
}

// Switching shadows off between frames of one backend is planned and recorded at once.
TEST_F(SurfaceRendererTest, TurningShadowsOffDropsTheShadowRaysFromTheNextFrame) {
  const SurfaceScene box = make_cornell_box();
  surface::SurfaceRenderer renderer(device(), box);
  if (!renderer.can_shadow()) GTEST_SKIP() << "the device traces no rays";
  renderer.resize({16, 12});
  ASSERT_TRUE(renderer.shadows());  // the box's light casts shadows: on by default
  const std::string mode = renderer.modes().front();
  record_frame(renderer, box.camera, mode);
  EXPECT_NE(renderer.last_plan().find(frame::PassId::ShadowRays), nullptr);
  renderer.set_shadows(false);
  record_frame(renderer, box.camera, mode);
  EXPECT_EQ(renderer.last_plan().find(frame::PassId::ShadowRays), nullptr);
  bool said_why = false;
  for (const frame::SkippedPass& s : renderer.last_plan().skipped) said_why = said_why || (s.name == "shadow rays" && s.reason == "shadows are off");
  EXPECT_TRUE(said_why);
}

}  // namespace
}  // namespace prismoid::test
