#include "renderer/mixed/mixed_frame.hpp"

#include <cmath>
#include <memory>
#include <stdexcept>

#include "scene/input_error.hpp"

namespace prismoid::mixed {

std::string mixed_scene_problem(const volume::ResolveSettings& resolve) {
  if (resolve.quantity == volume::Quantity::Isosurface) return "an isosurface does not end at surfaces (it follows no depth limit)";
  if (resolve.march.enabled) return "a marched field does not end at surfaces (marching follows no depth limit)";
  return {};
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

MixedRenderer::MixedRenderer(const vk::Device& device, const TetMesh& volume, SurfaceScene surfaces)
    : device_(device),
      surfaces_(std::move(surfaces)),
      gpu_surfaces_(surface::upload(device, surfaces_)),
      forward_(device),
      volume_(device, volume) {}

MixedFrame MixedRenderer::render(const Camera& camera, const frame::FrameSettings& settings, VkExtent2D extent) {
  if (const std::string problem = mixed_scene_problem(settings.resolve); !problem.empty()) throw InputError("mixed scene", problem);
  if (settings.resolve.depth_limit) throw InputError("depth limit", "a mixed scene's surfaces give the depth where its rays end");
  MixedFrame f;
  surface::ForwardSettings forward;
  forward.read_depth = true;
  surface::ForwardImage surfaces = surface::render_forward(device_, forward_, gpu_surfaces_, camera, extent, forward);
  f.surface_rgba = std::move(surfaces.rgba);
  f.surface_depth = std::move(surfaces.depth);
  f.passes = surfaces.passes;
  frame::FrameSettings limited = settings;
  limited.resolve.depth_limit = std::make_shared<const std::vector<float>>(f.surface_depth);
  f.volume = volume_.render_offscreen(camera, limited, extent);
  f.passes.insert(f.passes.end(), f.volume.passes.begin(), f.volume.passes.end());
  f.display = composite_over_surfaces(f.volume, f.surface_rgba, settings.resolve);
  return f;
}

}  // namespace prismoid::mixed
