#include "renderer/mixed/mixed_frame.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "renderer/surface/surface_backend.hpp"
#include "renderer/surface/view_depth.hpp"
#include "scene/input_error.hpp"

namespace prismoid::mixed {

std::string mixed_scene_problem(const volume::ResolveSettings& resolve) {
  if (resolve.quantity == volume::Quantity::Isosurface) return "an isosurface does not end at surfaces (it follows no depth limit)";
  if (resolve.march.enabled) return "a marched field does not end at surfaces (marching follows no depth limit)";
  return {};
}

void check_mixed_settings(const volume::ResolveSettings& resolve) {
  if (const std::string problem = mixed_scene_problem(resolve); !problem.empty()) throw InputError("mixed scene", problem);
  if (resolve.depth_limit) throw InputError("depth limit", "a mixed scene's surfaces give the depth where its rays end");
}

MixedPlan mixed_plan(frame::FramePlan surfaces, frame::FramePlan volume, volume::Quantity quantity) {
  std::erase_if(volume.skipped, [](const frame::SkippedPass& s) { return s.name == "surface-shading" || s.name == "gi"; });
  MixedPlan plan{std::move(surfaces), std::move(volume), {}};
  plan.composite = quantity == volume::Quantity::Color
                       ? "the volume's colour over the shaded surfaces, C_volume + (1 - A_volume) C_surface"
                       : "the shaded surfaces seen through the medium, medium (1 - T) + T C_surface";
  return plan;
}

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::string surface_mode_problem(const surface::SurfaceMode& mode) {
  if (!mode.gpu())
    return "'" + std::string(mode.name) + "' traces paths on the CPU and keeps no depth per pixel for a volume's rays to end at; "
           "the mixed scene's CPU reference lights the surfaces directly instead";
  return {};
}

MixedPlan plan_mixed_frame(const SurfaceScene& surfaces, const surface::SurfaceMode& mode, bool shadows, const TetMesh& volume,
                           const frame::FrameSettings& settings) {
  if (const std::string problem = surface_mode_problem(mode); !problem.empty()) throw InputError("surface mode", problem);
  frame::SurfaceFrameSettings s;
  s.mode = mode.name;
  s.passes = mode.backend->passes;
  s.gi = mode.gi;
  s.shadows = shadows;
  s.device_traces_rays = true;
  frame::SceneContents contents;
  contents.volumes.push_back(frame::volume_contents(volume, settings.resolve));
  return mixed_plan(frame::plan_surface_frame(surface::surface_contents(surfaces), s), frame::plan_frame(contents, settings),
                    settings.resolve.quantity);
}

std::vector<float> composite_over_surfaces(const frame::OffscreenFrame& volume, std::span<const float> surface_rgba,
                                           const volume::ResolveSettings& resolve) {
  const size_t pixels = size_t(volume.width) * volume.height;
  if (surface_rgba.size() != 4 * pixels || volume.quantity.size() != pixels)
    throw std::invalid_argument("composite_over_surfaces: the volume's and the surfaces' images differ in size");
  const bool color = resolve.quantity == volume::Quantity::Color;
  if (color && volume.emission.size() != 4 * pixels) throw std::invalid_argument("composite_over_surfaces: a colour frame without its emission");
  std::vector<float> out(4 * pixels);
  for (size_t i = 0; i < pixels; ++i) {
    const float* behind = &surface_rgba[4 * i];
    if (color) {
      const float* c = &volume.emission[4 * i];
      for (int k = 0; k < 3; ++k) out[4 * i + k] = float(double(c[k]) + (1.0 - double(c[3])) * double(behind[k]));
    } else {
      const double q = volume.quantity[i];
      const double t = resolve.quantity == volume::Quantity::Transmittance ? q : std::exp(-q);
      for (int k = 0; k < 3; ++k) out[4 * i + k] = float(double(resolve.medium[k]) * (1.0 - t) + t * double(behind[k]));
    }
    out[4 * i + 3] = 1.0f;
  }
  return out;
}

MixedRenderer::MixedRenderer(const vk::Device& device, const TetMesh& volume, const SurfaceScene& surfaces)
    : device_(device), surfaces_(device, surfaces), volume_(device, volume) {}

MixedFrame MixedRenderer::render(const Camera& camera, const frame::FrameSettings& settings, VkExtent2D extent,
                                 const std::string& surface_mode) {
  check_mixed_settings(settings.resolve);
  const surface::SurfaceMode* mode = surface::find_surface_mode(surface_mode);
  if (!mode) throw InputError("surface mode", "'" + surface_mode + "' is not a surface mode");
  if (const std::string problem = surface_mode_problem(*mode); !problem.empty()) throw InputError("surface mode", problem);
  if (const std::string problem = surfaces_.mode_problem(surface_mode); !problem.empty()) throw InputError("surface mode", problem);
  MixedFrame f;
  f.surface_mode = surface_mode;
  surface::SurfaceRenderer::Offscreen shaded = surfaces_.render_offscreen(camera, surface_mode, extent);
  f.surface_rgba = std::move(shaded.rgba);
  // Every surface backend draws its depth pre-pass each frame: the last one's depth is the
  // surfaces' seen in the colour (one sub-pixel position; GI modes' still frames share the camera).
  f.surface_depth = surface::read_view_axis_depth(device_, surfaces_.depth(), camera.near_distance);
  f.shadows = shaded.plan.find(frame::PassId::ShadowRays) != nullptr;
  f.passes = shaded.passes;
  frame::FrameSettings limited = settings;
  limited.resolve.depth_limit = std::make_shared<const std::vector<float>>(f.surface_depth);
  f.volume = volume_.render_offscreen(camera, limited, extent);
  f.passes.insert(f.passes.end(), f.volume.passes.begin(), f.volume.passes.end());
  const auto start = std::chrono::steady_clock::now();
  f.display = composite_over_surfaces(f.volume, f.surface_rgba, settings.resolve);
  f.cpu_passes = f.volume.report.cpu_passes;
  f.cpu_passes.push_back({kCompositePass, ms_since(start)});
  f.plan = mixed_plan(std::move(shaded.plan), f.volume.report.plan, settings.resolve.quantity);
  return f;
}

}  // namespace prismoid::mixed
