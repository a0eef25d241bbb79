#pragma once
// A frame's stats, typed (issue "One renderer for every front end"): every counter, setting and
// time a front end reports of a SceneFrame is a field here, filled in one place (SceneRenderer,
// from the renderers that drew the frame). The CLI writes them through one text writer and one
// JSON writer (app/common/frame_stats_writer.hpp); the window's panel and the plugin read the same
// fields. Nothing here is text: a writer chooses how a field reads.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/frame/frame_report.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/reference/path_tracer.hpp"
#include "renderer/surface/surface_backend.hpp"
#include "renderer/timing/frame_timing.hpp"
#include "renderer/vk/timer.hpp"

namespace prismoid::mixed {

// The volume of a volume frame or of a mixed one.
struct VolumeStats {
  std::string dataset;
  uint64_t cells = 0;
  std::string mode;                // its row of frame::volume_mode_table()
  frame::FrameSettings settings;   // as drawn: an automatic backend resolved, with its reason
  frame::FrameReport report;       // what its frame did: ordering, backend and its memory, counts, CPU passes, plan, warnings
  bool analytic_field = false;     // the volume samples an analytic field (march step, isovalue apply)
};

// The surfaces of a GPU surface frame (surfaces alone).
struct SurfaceStats {
  std::string scene;
  std::string mode;             // its row of surface::surface_mode_table() as drawn
  uint64_t triangles = 0, emitters = 0;
  uint64_t gpu_scene_bytes = 0;
  uint64_t covered_pixels = 0;  // pixels a surface covers
  bool shadows = false;         // the plan traced shadow rays
  bool default_lighting = false;  // the scene had no lights: the front end gave it the default ones
  uint32_t supersample = 1;
  bool takes_supersample = false, takes_frames = false;  // the mode's backend has those options
  surface::BackendCounts counts;  // the backend's own counters and settings
  uint32_t gi_frames = 0;         // a GI mode's frames gathered by its reservoirs
};

// The surfaces beside a volume (a mixed frame).
struct MixedSurfaceStats {
  std::string scene;
  uint64_t triangles = 0;
  std::string mode;  // the surfaces' mode, "reference" on the CPU
  bool shadows = false;
};

// Surfaces alone, path traced on the CPU.
struct PathStats {
  std::string scene;
  std::string mode;
  reference::PathTracerSettings settings;  // its samples per pixel, bounces and seed
  reference::PathTracerCounts counts;      // rays, and what its guards caught
  double seconds = 0.0;                    // the render's wall-clock time
  bool default_lighting = false;
};

struct FrameStats {
  std::string device, driver;  // the GPU's name and driver, or which CPU reference drew it
  bool gpu = false;
  uint32_t width = 0, height = 0;
  uint32_t frames = 1;  // frames timed (an interactive frame: 1)
  // What was drawn: a volume, surfaces alone (on the GPU, or path traced), or a volume inside
  // surfaces (volume and mixed).
  std::optional<VolumeStats> volume;
  std::optional<SurfaceStats> surfaces;
  std::optional<MixedSurfaceStats> mixed;
  std::optional<PathStats> path;
  // Time: the frame's GPU passes (the medians where frames were timed; a CPU volume reference's
  // stages, in CPU milliseconds), its CPU passes, and the spread over the timed frames.
  std::vector<vk::PassTiming> passes;
  std::vector<vk::PassTiming> cpu_passes;
  std::optional<timing::FrameTiming> timing;
  // The plan: a volume's or the surfaces' (plan), or a mixed frame's (mixed_plan).
  std::optional<frame::FramePlan> plan;
  std::optional<MixedPlan> mixed_plan;
  std::vector<std::string> warnings;

  // The sum of `passes`.
  double passes_ms() const;
};

}  // namespace prismoid::mixed
