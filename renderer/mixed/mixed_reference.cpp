#include "renderer/mixed/mixed_reference.hpp"

#include <chrono>
#include <limits>
#include <memory>

#include <glm/geometric.hpp>

#include "renderer/volume/cpu/reference_frame.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/input_error.hpp"

namespace prismoid::mixed {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::vector<float> first_hit_depth(const reference::DirectLightImage& image, const Camera& camera) {
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  std::vector<float> depth(image.pixels.size(), std::numeric_limits<float>::infinity());
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      const size_t i = size_t(y) * image.width + x;
      if (!image.pixels[i].hit) continue;
      // The direction direct_light_image traced this pixel along (its sample point: the centre).
      const glm::dvec3 d = reference::ray_direction(camera, image.width, image.height, x + 0.5, y + 0.5);
      depth[i] = float(image.pixels[i].t * glm::dot(d, forward));
    }
  return depth;
}

MixedFrame render_mixed_reference(const TetMesh& volume, const SurfaceScene& surfaces, const Camera& camera,
                                  const volume::ResolveSettings& resolve, VkExtent2D size, bool shadows) {
  check_mixed_settings(resolve);
  MixedFrame f;
  f.surface_mode = "reference";
  f.shadows = shadows;
  auto start = std::chrono::steady_clock::now();
  reference::DirectLightOptions options;
  options.shadows = shadows;
  const reference::DirectLightImage lit = reference::direct_light_image(surfaces, camera, size.width, size.height, 0.0, 0.0, options);
  f.surface_rgba.resize(4 * lit.pixels.size());
  for (size_t i = 0; i < lit.pixels.size(); ++i) {
    for (int k = 0; k < 3; ++k) f.surface_rgba[4 * i + k] = float(lit.pixels[i].radiance[k]);  // the sky where nothing is hit
    f.surface_rgba[4 * i + 3] = lit.pixels[i].hit ? 1.0f : 0.0f;
  }
  f.surface_depth = first_hit_depth(lit, camera);
  f.cpu_passes.push_back({shadows ? "surface reference, with shadows (CPU, double)" : "surface reference (CPU, double)", ms_since(start)});
  volume::ResolveSettings limited = resolve;
  limited.depth_limit = std::make_shared<const std::vector<float>>(f.surface_depth);
  f.volume = frame::render_reference(volume, camera, limited, size);
  f.cpu_passes.insert(f.cpu_passes.end(), f.volume.passes.begin(), f.volume.passes.end());
  start = std::chrono::steady_clock::now();
  f.display = composite_over_surfaces(f.volume, f.surface_rgba, resolve);
  f.cpu_passes.push_back({kCompositePass, ms_since(start)});
  f.plan = mixed_plan({}, {}, resolve.quantity);
  return f;
}

}  // namespace prismoid::mixed
