#pragma once
// What the frame planner reads of a volume backend: its part of a frame as plain data (each
// backend's line of the volume backend table gives it, renderer/volume/volume_backend.hpp).
// The planner composes the shared passes (the transfer function's, the resolve) with these.
// No Vulkan here.
#include <string>
#include <string_view>
#include <vector>

#include "renderer/frame/frame_plan.hpp"

namespace prismoid::frame {

struct VolumePasses {
  std::string_view backend;  // its name, for the reasons
  // Draws cells in the order the mode asks for: the ordering passes (sort, exact order) are
  // planned where the quantity is order dependent. Else it orders each pixel itself, and
  // `own_order` says how (the reason the ordering passes are left out for colour).
  bool chosen_order = true;
  std::string_view own_order;
  std::string_view isosurface_order;  // why an isosurface needs no order, where it is said its own way
  // Groups cells into tetlets (shared vertices). Else `no_tetlets` says why none are built and
  // `tetlets_refused` why --shared-vertices is refused.
  bool tetlets = true;
  std::string_view no_tetlets;
  std::string_view tetlets_refused;
  // Its GPU passes that draw the intervals into the accumulation targets, each with why (and
  // those it leaves out), for this volume and these settings.
  void (*intervals)(const VolumeContents& volume, const FrameSettings& settings, std::vector<PlannedPass>& run,
                    std::vector<SkippedPass>& skipped) = nullptr;
};

// Why a volume's intervals are integrated as they are (its optics, field model, tables,
// tetlets and cells per workgroup): the shared part of an interval pass's reason.
std::string interval_reason(const VolumeContents& volume, const FrameSettings& settings);

// The frame of `scene` with `settings`, its volume drawn by the backend `passes` describe.
// Throws InputError for settings no plan satisfies (tetlets with an ordered colour mode, or
// with a backend that builds none). plan_frame(scene, settings) is this with the passes of the
// backend settings.backend names (renderer/volume/volume_backends.cpp).
FramePlan plan_frame(const SceneContents& scene, const FrameSettings& settings, const VolumePasses& passes);

}  // namespace prismoid::frame
