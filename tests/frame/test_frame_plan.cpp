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

}  // namespace
}  // namespace prismoid
