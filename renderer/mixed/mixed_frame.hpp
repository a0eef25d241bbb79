#pragma once
// A volume inside its geometry, in one frame (issue "A volume inside its geometry"). Every
// surface is opaque: a pixel's ray crosses the volume from the near plane up to the first surface
// it meets (or to infinity), so the volume's quantity (optical depth, transmittance, colour) is
// integrated over that part only, and what the ray sees behind the volume is the shaded surface
// there (the sky where it meets none). The frame: the surfaces (any GPU surface mode through
// surface::SurfaceRenderer, every one of which draws a depth buffer; that depth read back along
// the viewing axis), the volume with each ray ending at that depth
// (volume::ResolveSettings::depth_limit, both backends), then the volume composited over the
// surfaces: C = C_volume + (1 - A_volume) C_surface for colour; absorption-only quantities show
// the surface through the medium, medium (1 - T) + T C_surface.
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::mixed {

// A mixed frame's plan: the surfaces' passes, the volume's (its rays ended at the surfaces), and the
// composite on the CPU, each with why and what each left out; the volume's skips of surface
// passes are left out (the surfaces' plan says what of them runs).
struct MixedPlan {
  frame::FramePlan surfaces;
  frame::FramePlan volume;
  std::string composite;  // the composite's rule, for this quantity
};
MixedPlan mixed_plan(frame::FramePlan surfaces, frame::FramePlan volume, volume::Quantity quantity);
// The plan of a mixed frame of a GPU surface mode (on a device that traces rays; `shadows` asked
// for) and these volume settings, before any frame ran (`info --plan`): pure, as frame::plan_frame.
MixedPlan plan_mixed_frame(const SurfaceScene& surfaces, const surface::SurfaceMode& mode, bool shadows, const TetMesh& volume,
                           const frame::FrameSettings& settings);

// Why `mode` cannot shade the surfaces around a volume (the CPU path tracer keeps no depth per
// pixel and has a reference of its own); empty when it can.
std::string surface_mode_problem(const surface::SurfaceMode& mode);

// The composite's timing entry in MixedFrame::cpu_passes.
inline constexpr const char* kCompositePass = "composite";

struct MixedFrame {
  frame::OffscreenFrame volume;        // the volume's frame, its rays ended at the surfaces
  std::string surface_mode;            // the surfaces' mode (surface_modes.hpp), "reference" on the CPU
  bool shadows = false;                // the surfaces were shaded with shadow rays
  std::vector<float> surface_rgba;     // the surfaces shaded: linear RGBA, alpha = coverage (sky where 0)
  std::vector<float> surface_depth;    // per pixel, the nearest surface's depth along the viewing axis (+inf: none)
  std::vector<float> display;          // the composite: linear RGBA, alpha 1
  std::vector<vk::PassTiming> passes;      // GPU: the surfaces' passes, then the volume's
  std::vector<vk::PassTiming> cpu_passes;  // CPU (gpu_ms holds the CPU time): the volume's, then the composite
  MixedPlan plan;                      // what ran and why (the GPU frame's)
};

// Why a volume frame of these settings cannot end its rays at surfaces (the marching modes and
// isosurfaces follow no depth limit); empty when it can.
std::string mixed_scene_problem(const volume::ResolveSettings& resolve);
// InputError for settings mixed_scene_problem names, or that bring a depth limit of their own
// (the surfaces give it).
void check_mixed_settings(const volume::ResolveSettings& resolve);

// The volume's frame over the surfaces' image (linear RGBA per pixel), as the header says: the
// returned display image, alpha 1. Colour needs `volume.emission` (premultiplied RGB, alpha);
// std::invalid_argument when the sizes differ.
std::vector<float> composite_over_surfaces(const frame::OffscreenFrame& volume, std::span<const float> surface_rgba,
                                           const volume::ResolveSettings& resolve);

class MixedRenderer {
 public:
  // `surfaces` must carry its lights already (with_default_lighting where it has none of its own).
  MixedRenderer(const vk::Device& device, const TetMesh& volume, const SurfaceScene& surfaces);

  // One frame: the surfaces in `surface_mode`, the volume ending at them, the composite.
  // InputError as check_mixed_settings, for a mode surface_mode_problem names, or one this
  // device cannot draw.
  MixedFrame render(const Camera& camera, const frame::FrameSettings& settings, VkExtent2D extent,
                    const std::string& surface_mode = "forward");

  // The surfaces' renderer: its modes, and its shadows setting (on by default where the device
  // traces rays and a light casts shadows).
  surface::SurfaceRenderer& surface_renderer() { return surfaces_; }
  frame::FrameRenderer& volume_renderer() { return volume_; }

 private:
  const vk::Device& device_;
  surface::SurfaceRenderer surfaces_;
  frame::FrameRenderer volume_;
};

}  // namespace prismoid::mixed
