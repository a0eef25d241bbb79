// The frame planner (renderer/frame/frame_plan): which passes a frame runs for a table of
// small scenes and settings, exactly, and why the others do not run.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "scene/input_error.hpp"

namespace prismoid {
namespace {

using frame::Ordering;
using volume::Quantity;

// What the last frame left: nothing (a first frame), or a recorded frame from another eye
// or the same eye, with the order buffer made by `kept`.
enum class History { First, CameraMoved, Still, StillSceneChanged };

struct Case {
  const char* what;
  Quantity quantity;
  bool march;
  Ordering ordering;
  uint32_t preintegration;  // table size; 0: exact segments
  History history;
  bool transfer_changed;    // ignored for a first frame (everything changed)
  Ordering kept;            // the ordering of the last frame's order buffer
  std::vector<std::string> passes;  // exactly, in order
};

frame::FrameSettings settings_of(const Case& c) {
  frame::FrameSettings s;
  s.resolve.quantity = c.quantity;
  s.resolve.march.enabled = c.march;
  s.resolve.march.step = 0.05;
  s.resolve.preintegration_size = c.preintegration;
  s.ordering = c.ordering;
  return s;
}

frame::SceneContents scene_of(const Case& c, const frame::FrameSettings& s) {
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(48, true, true, s.resolve));
  if (c.history == History::First) return scene;
  scene.camera_moved = c.history == History::CameraMoved;
  scene.scene_moved = c.history == History::StillSceneChanged;
  scene.transfer_changed = c.transfer_changed;
  scene.order_kept = c.kept;
  scene.tetlets_built = true;
  return scene;
}

std::vector<std::string> names(const frame::FramePlan& plan) {
  std::vector<std::string> v;
  for (const auto& p : plan.passes) v.push_back(p.name);
  return v;
}

std::string skip_reason(const frame::FramePlan& plan, const std::string& name) {
  for (const auto& s : plan.skipped)
    if (s.name == name) return s.reason;
  return "";
}

const std::string kEmission = "interval-shading (emission)";
constexpr Quantity kDepth = Quantity::OpticalDepth, kTrans = Quantity::Transmittance, kColor = Quantity::Color;
constexpr Ordering kMesh = Ordering::MeshOrder, kSort = Ordering::GpuSort, kExact = Ordering::Exact;

const std::vector<Case> kCases = {
    // Order-independent quantities never order anything, whatever the mode asks for.
    {"optical depth, sorted mode", kDepth, false, kSort, 0, History::First, true, kSort, {"interval-shading", "resolve"}},
    {"optical depth, exact mode", kDepth, false, kExact, 0, History::First, true, kSort, {"interval-shading", "resolve"}},
    {"transmittance, mesh order", kTrans, false, kMesh, 0, History::First, true, kSort, {"interval-shading", "resolve"}},
    {"transmittance, camera moved", kTrans, false, kSort, 0, History::CameraMoved, false, kSort, {"interval-shading", "resolve"}},
    {"optical depth marched", kDepth, true, kSort, 0, History::First, true, kSort, {"interval-march", "resolve"}},
    {"isosurface marched, exact mode", Quantity::Isosurface, true, kExact, 0, History::First, true, kSort,
     {"interval-march (isosurface)", "resolve"}},
    // Colour: the transfer function goes up when it changed; a table is built when asked for.
    {"colour, mesh order", kColor, false, kMesh, 0, History::First, true, kSort, {"transfer-function upload", kEmission, "resolve"}},
    {"colour, sorted", kColor, false, kSort, 0, History::First, true, kSort, {"transfer-function upload", "sort", kEmission, "resolve"}},
    {"colour, sorted, table", kColor, false, kSort, 32, History::First, true, kSort, {"preintegrate", "sort", kEmission, "resolve"}},
    {"colour, exact", kColor, false, kExact, 0, History::First, true, kSort,
     {"transfer-function upload", "exact-order", "upload-order", kEmission, "resolve"}},
    {"colour, exact, table", kColor, false, kExact, 16, History::First, true, kSort,
     {"preintegrate", "exact-order", "upload-order", kEmission, "resolve"}},
    {"colour marched, sorted", kColor, true, kSort, 0, History::First, true, kSort,
     {"transfer-function upload", "sort", "interval-march (color)", "resolve"}},
    // Later frames: an unchanged table is not rebuilt; a moved camera re-orders.
    {"colour, sorted, table unchanged, camera moved", kColor, false, kSort, 32, History::CameraMoved, false, kSort,
     {"sort", kEmission, "resolve"}},
    {"colour, sorted, table changed, camera moved", kColor, false, kSort, 32, History::CameraMoved, true, kSort,
     {"preintegrate", "sort", kEmission, "resolve"}},
    {"colour, exact, camera moved", kColor, false, kExact, 0, History::CameraMoved, false, kExact,
     {"exact-order", "upload-order", kEmission, "resolve"}},
    {"colour, mesh order, camera moved", kColor, false, kMesh, 0, History::CameraMoved, false, kMesh, {kEmission, "resolve"}},
    // A still camera reuses the order its ordering made; another ordering's order is not reused.
    {"colour, sorted, still", kColor, false, kSort, 0, History::Still, false, kSort, {kEmission, "resolve"}},
    {"colour, sorted, table, still", kColor, false, kSort, 32, History::Still, false, kSort, {kEmission, "resolve"}},
    {"colour, exact, still", kColor, false, kExact, 0, History::Still, false, kExact, {kEmission, "resolve"}},
    {"colour, exact, still, transfer changed", kColor, false, kExact, 0, History::Still, true, kExact,
     {"transfer-function upload", kEmission, "resolve"}},
    {"colour, exact, still, last order sorted", kColor, false, kExact, 0, History::Still, false, kSort,
     {"exact-order", "upload-order", kEmission, "resolve"}},
    {"colour, sorted, still, last order exact", kColor, false, kSort, 0, History::Still, false, kExact, {"sort", kEmission, "resolve"}},
    {"colour, sorted, still, scene changed", kColor, false, kSort, 0, History::StillSceneChanged, false, kSort,
     {"sort", kEmission, "resolve"}},
    {"colour marched, exact, still", kColor, true, kExact, 0, History::Still, false, kExact, {"interval-march (color)", "resolve"}},
};

TEST(FramePlan, PlansExactlyThePassesEachSceneAndSettingCallFor) {
  for (const Case& c : kCases) {
    const frame::FrameSettings s = settings_of(c);
    const frame::FramePlan plan = frame::plan_frame(scene_of(c, s), s);
    EXPECT_EQ(names(plan), c.passes) << c.what;
    for (const auto& p : plan.passes) EXPECT_FALSE(p.reason.empty()) << c.what << ": " << p.name;
  }
}

// Every pass the planner knows is either planned or skipped with a reason, never both, never neither.
TEST(FramePlan, AccountsForEveryPassOnce) {
  const std::set<std::string> known = {"transfer-function upload", "preintegrate", "build-tetlets", "exact-order", "sort",
                                       "upload-order", "surface-shading", "gi"};
  for (const Case& c : kCases) {
    const frame::FrameSettings s = settings_of(c);
    const frame::FramePlan plan = frame::plan_frame(scene_of(c, s), s);
    std::multiset<std::string> seen;
    for (const auto& p : plan.passes) seen.insert(p.name);
    for (const auto& p : plan.skipped) {
      seen.insert(p.name);
      EXPECT_FALSE(p.reason.empty()) << c.what << ": " << p.name;
    }
    for (const std::string& name : known) {
      // Exact segments leave "transfer-function upload" out of the candidates only for non-colour frames.
      if (name == "transfer-function upload" && (c.quantity != kColor || c.preintegration > 0)) continue;
      EXPECT_EQ(seen.count(name), 1u) << c.what << ": " << name;
    }
  }
}

TEST(FramePlan, SkippedPassesSayWhy) {
  frame::FrameSettings s;
  s.resolve.quantity = kDepth;
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(10, false, false, s.resolve));
  frame::FramePlan plan = frame::plan_frame(scene, s);
  EXPECT_NE(skip_reason(plan, "sort").find("optical depth is order-independent"), std::string::npos);
  EXPECT_NE(skip_reason(plan, "gi").find("no indirect light"), std::string::npos);
  EXPECT_NE(skip_reason(plan, "surface-shading").find("no surfaces"), std::string::npos);

  s.resolve.quantity = kColor;
  s.resolve.preintegration_size = 32;
  scene.volumes = {frame::volume_contents(10, false, true, s.resolve)};
  scene.camera_moved = scene.scene_moved = false;
  scene.transfer_changed = false;
  scene.order_kept = kSort;
  plan = frame::plan_frame(scene, s);
  EXPECT_TRUE(plan.reuses_order);
  EXPECT_EQ(skip_reason(plan, "preintegrate").rfind("table unchanged", 0), 0u);
  EXPECT_EQ(skip_reason(plan, "sort").rfind("order reused: camera still", 0), 0u);

  // Indirect light wanted but nothing to gather it from: no GI pass.
  scene.indirect_wanted = true;
  EXPECT_NE(skip_reason(frame::plan_frame(scene, s), "gi").find("no surfaces: nothing indirect to gather"), std::string::npos);
  scene.surfaces = 2;
  EXPECT_NE(skip_reason(frame::plan_frame(scene, s), "gi").find("nothing to gather"), std::string::npos);
  EXPECT_FALSE(frame::plan_frame(scene, s).has("gi"));
}

TEST(FramePlan, TetletsAreBuiltOncePerSize) {
  frame::FrameSettings s;
  s.resolve.quantity = kDepth;
  s.resolve.shared_vertices = true;
  s.resolve.tetlet_size = 8;
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(10, false, false, s.resolve));
  EXPECT_EQ(names(frame::plan_frame(scene, s)), (std::vector<std::string>{"build-tetlets", "interval-shading", "resolve"}));
  scene.tetlets_built = true;
  EXPECT_EQ(names(frame::plan_frame(scene, s)), (std::vector<std::string>{"interval-shading", "resolve"}));
  EXPECT_NE(frame::plan_frame(scene, s).passes[0].reason.find("tetlets (shared vertices)"), std::string::npos);
}

TEST(FramePlan, TetletsWithAnOrderedColourModeAreRefused) {
  frame::FrameSettings s;
  s.resolve.quantity = kColor;
  s.resolve.shared_vertices = true;
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(10, false, true, s.resolve));
  EXPECT_THROW(frame::plan_frame(scene, s), InputError);
  s.ordering = kMesh;
  EXPECT_NO_THROW(frame::plan_frame(scene, s));
}

// The compute backend: its three passes replace the interval pass, the resolve is shared, the
// transfer function goes up as for the mesh backend; nothing is ordered per cell (each pixel
// orders its own intervals), and the mesh shader's tetlets are refused, naming the option.
TEST(FramePlan, ComputeBackendBinsSortsAndRastersTiles) {
  const std::vector<std::string> compute = {"bin-cells", "tile-sort", "tile-raster", "resolve"};
  struct ComputeCase {
    Quantity quantity;
    bool march;
    uint32_t table;
    std::vector<std::string> cpu;
  };
  const ComputeCase cases[] = {{kDepth, false, 0, {}},
                               {kTrans, false, 0, {}},
                               {kColor, false, 0, {"transfer-function upload"}},
                               {kColor, false, 32, {"preintegrate"}},
                               {kDepth, true, 0, {}},
                               {kColor, true, 0, {"transfer-function upload"}},
                               {Quantity::Isosurface, true, 0, {}}};
  for (const ComputeCase& c : cases) {
    for (Ordering ordering : {kMesh, kSort, kExact}) {
      frame::FrameSettings s;
      s.backend = frame::IntervalBackend::Compute;
      s.resolve.quantity = c.quantity;
      s.resolve.march.enabled = c.march;
      s.resolve.march.step = 0.05;
      s.resolve.preintegration_size = c.table;
      s.ordering = ordering;
      frame::SceneContents scene;
      scene.volumes.push_back(frame::volume_contents(48, true, true, s.resolve));
      const frame::FramePlan plan = frame::plan_frame(scene, s);
      std::vector<std::string> expected = c.cpu;
      expected.insert(expected.end(), compute.begin(), compute.end());
      EXPECT_EQ(names(plan), expected) << volume::interval_pass_name(s.resolve);
      EXPECT_EQ(plan.gpu_pass_names(), compute);
      for (const char* skipped : {"exact-order", "sort", "upload-order", "build-tetlets"})
        EXPECT_FALSE(skip_reason(plan, skipped).empty()) << skipped;
      EXPECT_NE(skip_reason(plan, volume::interval_pass_name(s.resolve)).find("compute backend"), std::string::npos);
      for (const auto& p : plan.passes) EXPECT_FALSE(p.reason.empty()) << p.name;
      if (c.quantity == kColor) {
        EXPECT_NE(plan.find(frame::PassId::TileRaster)->reason.find("each pixel's own depth order"), std::string::npos);
      }
    }
  }
  frame::FrameSettings s;
  s.backend = frame::IntervalBackend::Compute;
  s.resolve.quantity = kDepth;
  s.resolve.shared_vertices = true;
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(10, false, false, s.resolve));
  try {
    frame::plan_frame(scene, s);
    ADD_FAILURE() << "tetlets with the compute backend were planned";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "shared-vertices");
  }
  EXPECT_STREQ(frame::interval_backend_name(frame::IntervalBackend::Compute), "compute");
  EXPECT_STREQ(frame::interval_backend_name(frame::IntervalBackend::Mesh), "mesh");
}

TEST(FramePlan, AnEmptyMeshOrdersNothing) {
  frame::FrameSettings s;
  s.resolve.quantity = kColor;
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(0, false, true, s.resolve));
  EXPECT_FALSE(frame::plan_frame(scene, s).has("sort"));
}

TEST(FramePlan, VolumeContentsFollowTheFieldTheFrameIntegrates) {
  volume::ResolveSettings r;
  r.quantity = kDepth;
  EXPECT_EQ(frame::volume_contents(1, false, true, r).field, frame::FieldModel::PerCell);
  EXPECT_EQ(frame::volume_contents(1, true, false, r).field, frame::FieldModel::Linear);
  EXPECT_EQ(frame::volume_contents(1, true, false, r).optics, frame::VolumeOptics::AbsorptionOnly);
  r.quantity = kColor;  // colour integrates the scalar field, not the extinction
  EXPECT_EQ(frame::volume_contents(1, true, false, r).field, frame::FieldModel::PerCell);
  EXPECT_EQ(frame::volume_contents(1, false, true, r).field, frame::FieldModel::Linear);
  EXPECT_EQ(frame::volume_contents(1, false, true, r).optics, frame::VolumeOptics::EmissionAbsorption);
  r.march.enabled = true;
  EXPECT_EQ(frame::volume_contents(1, false, true, r).field, frame::FieldModel::Marched);
}

// ---- Surface frames ----

// Two backends as the planner sees them: a per-pixel one (pre-pass and shading, no atlas, no
// display pass, no GI) and a texture-space one hosting GI (every role a pass).
frame::SurfacePasses per_pixel_passes() {
  frame::SurfacePasses p;
  p.pre_z = {"depth pre-pass", "depth only", "depth and each pixel's triangle"};
  p.allocation = {"", "per pixel: no texture-space samples to allocate", ""};
  p.shading = {"pixel shading", "raster shading", "ray-generation shading"};
  p.shadow_rays = {"shadow rays", "one ray per light", ""};
  p.display = {"", "the shading pass writes the image", ""};
  return p;
}
frame::SurfacePasses texture_space_passes() {
  frame::SurfacePasses p;
  p.pre_z = {"pre-z + marking", "marks", ""};
  p.allocation = {"allocation", "pages", ""};
  p.shading = {"shading", "texels", ""};
  p.shadow_rays = {"shadow rays", "one ray per light", ""};
  p.gi = {{"gi samples", "samples", ""}, {"gi reuse", "reservoirs", ""}};
  p.display = {"gather", "pixels", ""};
  return p;
}

struct SurfaceCase {
  const char* what;
  frame::SurfacePasses passes;
  frame::SurfaceGi gi;
  frame::SurfaceContents scene;
  bool shadows;
  bool traces;
  std::vector<std::string> planned;  // exactly, in order (shadow rays: within the pass before)
  std::vector<std::string> skipped;  // exactly, in order
};

frame::SurfaceContents surface_scene(uint32_t point, uint32_t directional, uint32_t emissive, bool sky, uint64_t triangles = 36) {
  frame::SurfaceContents c;
  c.triangles = triangles;
  c.point_lights = point;
  c.directional_lights = directional;
  c.emissive_triangles = emissive;
  c.sky = sky;
  return c;
}

const std::vector<SurfaceCase> kSurfaceCases = {
    {"per pixel, a light that casts shadows, ray tracing", per_pixel_passes(), frame::SurfaceGi::None, surface_scene(1, 0, 0, false), true, true,
     {"depth pre-pass", "pixel shading", "shadow rays"}, {"allocation", "gi", "display"}},
    {"per pixel, no ray tracing", per_pixel_passes(), frame::SurfaceGi::None, surface_scene(1, 0, 0, false), true, false,
     {"depth pre-pass", "pixel shading"}, {"allocation", "shadow rays", "gi", "display"}},
    {"per pixel, shadows off", per_pixel_passes(), frame::SurfaceGi::None, surface_scene(0, 1, 0, true), false, true,
     {"depth pre-pass", "pixel shading"}, {"allocation", "shadow rays", "gi", "display"}},
    {"per pixel, only the sky: nothing casts shadows", per_pixel_passes(), frame::SurfaceGi::None, surface_scene(0, 0, 0, true), true, true,
     {"depth pre-pass", "pixel shading"}, {"allocation", "shadow rays", "gi", "display"}},
    {"texture space, emitters cast shadows", texture_space_passes(), frame::SurfaceGi::None, surface_scene(0, 0, 4, false), true, true,
     {"pre-z + marking", "allocation", "shading", "shadow rays", "gather"}, {"gi"}},
    {"texture space, no lights at all", texture_space_passes(), frame::SurfaceGi::None, surface_scene(0, 0, 0, false), true, true,
     {"pre-z + marking", "allocation", "shading", "gather"}, {"shadow rays", "gi"}},
    {"GI asked, a light to bounce", texture_space_passes(), frame::SurfaceGi::RestirBiased, surface_scene(0, 1, 0, false), true, true,
     {"pre-z + marking", "allocation", "shading", "shadow rays", "gi samples", "gi reuse", "gather"}, {}},
    {"GI asked, only emitters to bounce, shadows off", texture_space_passes(), frame::SurfaceGi::RestirUnbiased, surface_scene(0, 0, 2, false), false, true,
     {"pre-z + marking", "allocation", "shading", "gi samples", "gi reuse", "gather"}, {"shadow rays"}},
    {"GI asked, only the sky to bounce", texture_space_passes(), frame::SurfaceGi::PathTraced, surface_scene(0, 0, 0, true), true, true,
     {"pre-z + marking", "allocation", "shading", "gi samples", "gi reuse", "gather"}, {"shadow rays"}},
    {"GI asked, nothing lights the scene", texture_space_passes(), frame::SurfaceGi::RestirBiased, surface_scene(0, 0, 0, false), true, true,
     {"pre-z + marking", "allocation", "shading", "gather"}, {"shadow rays", "gi"}},
    {"no surfaces", texture_space_passes(), frame::SurfaceGi::RestirBiased, surface_scene(1, 1, 1, true, 0), true, true,
     {}, {"pre-z", "allocation", "shading", "shadow rays", "gi", "display"}},
};

TEST(SurfaceFramePlan, PlansExactlyThePassesEachSceneAndSettingCallFor) {
  for (const SurfaceCase& c : kSurfaceCases) {
    frame::SurfaceFrameSettings s;
    s.mode = "test-mode";
    s.passes = c.passes;
    s.gi = c.gi;
    s.shadows = c.shadows;
    s.device_traces_rays = c.traces;
    const frame::FramePlan plan = frame::plan_surface_frame(c.scene, s);
    EXPECT_EQ(names(plan), c.planned) << c.what;
    std::vector<std::string> skipped;
    for (const auto& p : plan.skipped) {
      skipped.push_back(p.name);
      EXPECT_FALSE(p.reason.empty()) << c.what << ": " << p.name;
    }
    EXPECT_EQ(skipped, c.skipped) << c.what;
    for (const auto& p : plan.passes) {
      EXPECT_FALSE(p.reason.empty()) << c.what << ": " << p.name;
      // Shadow rays run inside the shading pass: planned and explained, never timed on their own.
      EXPECT_EQ(p.kind, p.name == "shadow rays" ? frame::PassKind::Within : frame::PassKind::Gpu) << c.what << ": " << p.name;
    }
    std::vector<std::string> timed = names(plan);
    timed.erase(std::remove(timed.begin(), timed.end(), "shadow rays"), timed.end());
    EXPECT_EQ(plan.gpu_pass_names(), timed) << c.what;
  }
}

TEST(SurfaceFramePlan, ReasonsNameWhatTheSceneAndSettingsSay) {
  frame::SurfaceFrameSettings s;
  s.mode = "test-gi";
  s.passes = per_pixel_passes();
  s.device_traces_rays = true;
  const frame::SurfaceContents lit = surface_scene(2, 1, 1280, true);
  frame::FramePlan plan = frame::plan_surface_frame(lit, s);
  // The pass's words with shadows, and the casters counted.
  EXPECT_EQ(plan.passes.at(0).reason, "depth and each pixel's triangle");
  EXPECT_EQ(plan.passes.at(1).reason, "ray-generation shading");
  EXPECT_EQ(plan.passes.at(2).reason, "2 point lights, 1 directional light and 1280 emissive triangles cast shadows: one ray per light");
  EXPECT_EQ(skip_reason(plan, "gi"), "no indirect light asked for (mode test-gi)");
  EXPECT_EQ(skip_reason(plan, "display"), "the shading pass writes the image");
  s.shadows = false;
  plan = frame::plan_surface_frame(lit, s);
  EXPECT_EQ(plan.passes.at(1).reason, "raster shading");
  EXPECT_EQ(skip_reason(plan, "shadow rays"), "shadows are off");
  s.device_traces_rays = false;
  EXPECT_EQ(skip_reason(frame::plan_surface_frame(lit, s), "shadow rays"), "the device traces no rays (no ray-tracing pipeline)");
  s.shadows = true;
  s.device_traces_rays = true;
  EXPECT_EQ(skip_reason(frame::plan_surface_frame(surface_scene(0, 0, 0, true), s), "shadow rays"), "no light casts shadows");

  s.passes = texture_space_passes();
  s.gi = frame::SurfaceGi::RestirUnbiased;
  plan = frame::plan_surface_frame(surface_scene(0, 0, 3, true, 10), s);
  ASSERT_NE(plan.find(frame::PassId::GlobalIllumination), nullptr);
  EXPECT_EQ(plan.find(frame::PassId::GlobalIllumination)->reason,
            "one-bounce indirect light asked for (mode test-gi: ReSTIR GI, unbiased), bouncing the light of 3 emissive triangles and the "
            "sky off 10 triangles: samples");
  EXPECT_NE(skip_reason(frame::plan_surface_frame(surface_scene(0, 0, 0, false), s), "gi").find("nothing to bounce"), std::string::npos);
  const std::string text = frame::format_plan(frame::plan_surface_frame(surface_scene(1, 0, 0, false), s));
  EXPECT_NE(text.find("\n  shadow rays (GPU, within the pass above): 1 point light casts shadows: one ray per light\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\n  gi samples (GPU): "), std::string::npos) << text;
}

// A mode that asks for GI its backend does not host is a table error, not a plan.
TEST(SurfaceFramePlan, GiTheBackendDoesNotHostIsRefused) {
  frame::SurfaceFrameSettings s;
  s.mode = "test-mode";
  s.passes = per_pixel_passes();
  s.gi = frame::SurfaceGi::RestirBiased;
  EXPECT_THROW(frame::plan_surface_frame(surface_scene(1, 0, 0, false), s), std::logic_error);
}

}  // namespace
}  // namespace prismoid
