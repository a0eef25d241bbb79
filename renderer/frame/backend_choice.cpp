#include "renderer/frame/backend_choice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/vk/device.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

BackendChoice choose_backend(const BackendCalibration& c) {
  char numbers[160];
  std::snprintf(numbers, sizeof numbers, "a %llu-cell calibration frame at %ux%u took %.3g ms with compute, %.3g ms with mesh shaders",
                static_cast<unsigned long long>(c.cells), c.width, c.height, c.compute_ms, c.mesh_ms);
  const bool measured = std::isfinite(c.mesh_ms) && std::isfinite(c.compute_ms) && c.mesh_ms > 0.0 && c.compute_ms > 0.0;
  if (!measured) {
    return {IntervalBackend::Mesh, std::string("auto: mesh shaders, the calibration could not time both backends (") + numbers + ")"};
  }
  if (c.compute_ms < c.mesh_ms) {
    char ratio[48];
    std::snprintf(ratio, sizeof ratio, "%.2gx faster", c.mesh_ms / c.compute_ms);
    return {IntervalBackend::Compute, std::string("auto: compute, ") + ratio + " on this device (" + numbers + ")"};
  }
  char ratio[48];
  std::snprintf(ratio, sizeof ratio, "%.2gx faster", c.compute_ms / c.mesh_ms);
  return {IntervalBackend::Mesh, std::string("auto: mesh shaders, ") + ratio + " on this device (" + numbers + ")"};
}

std::string device_key(const vk::Device& device) {
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(device.physical(), &props);
  char uuid[2 * VK_UUID_SIZE + 1] = {};
  for (uint32_t i = 0; i < VK_UUID_SIZE; ++i) std::snprintf(uuid + 2 * i, 3, "%02x", props.pipelineCacheUUID[i]);
  return std::string(props.deviceName) + " driver " + std::to_string(props.driverVersion) + " " + uuid;
}

BackendCalibration calibrate_backends(const vk::Device& device, uint32_t frames) {
  BackendCalibration c;
  c.device_key = device_key(device);
  c.width = c.height = 128;
  // A field that varies across the box, so no backend can skip work a real dataset has.
  const TetMesh mesh = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 12,
                                     [](const glm::dvec3& p) { return 1.0 + 0.5 * std::sin(3.0 * p.x) * std::cos(2.0 * p.y); });
  c.cells = mesh.tets.size();
  FrameRenderer renderer(device, mesh);
  const Camera camera = fit_camera(renderer.bounds());
  auto best_of = [&](IntervalBackend backend) {
    FrameSettings settings;
    settings.resolve.quantity = volume::Quantity::OpticalDepth;
    settings.backend = backend;
    double best = std::numeric_limits<double>::infinity();
    for (uint32_t i = 0; i <= frames; ++i) {
      renderer.forget_history();
      const OffscreenFrame frame = renderer.render_offscreen(camera, settings, {c.width, c.height});
      if (i > 0) best = std::min(best, vk::total_gpu_ms(frame.passes));  // the first frame builds pipelines
    }
    return best;
  };
  c.mesh_ms = best_of(IntervalBackend::Mesh);
  c.compute_ms = best_of(IntervalBackend::Compute);
  return c;
}

}  // namespace prismoid::frame
