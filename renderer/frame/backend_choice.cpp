#include "renderer/frame/backend_choice.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

BackendChoice choose_backend(const BackendCalibration& c) {
  std::vector<std::pair<std::string_view, double>> timed;  // in table order
  std::string untimed, numbers;
  for (const volume::VolumeBackendInfo* b : volume::volume_backend_table()) {
    if (!b->gpu()) continue;
    const auto found = c.ms.find(b->name);
    const double ms = found == c.ms.end() ? std::numeric_limits<double>::quiet_NaN() : found->second;
    if (std::isfinite(ms) && ms > 0.0) {
      timed.emplace_back(b->name, ms);
      char time[64];
      std::snprintf(time, sizeof time, "%.3g ms with %s", ms, std::string(b->name).c_str());
      numbers.append(numbers.empty() ? "" : ", ").append(time);
    } else {
      untimed.append(untimed.empty() ? "" : ", ").append(b->name);
    }
  }
  char frame[96];
  std::snprintf(frame, sizeof frame, "a %llu-cell calibration frame at %ux%u", static_cast<unsigned long long>(c.cells), c.width,
                c.height);
  const std::string measured = std::string(frame).append(numbers.empty() ? " was not timed" : " took " + numbers);
  if (timed.empty()) {
    const IntervalBackend fallback{volume::volume_backend_table().front()->name};
    return {fallback, std::string("auto: ").append(fallback.name).append(", the calibration could not time any backend (")
                          .append(measured).append(")")};
  }
  std::stable_sort(timed.begin(), timed.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  std::string why = std::string("auto: ").append(timed[0].first).append(", ");
  if (timed.size() > 1) {
    char ratio[48];
    std::snprintf(ratio, sizeof ratio, "%.2gx faster than %s", timed[1].second / timed[0].second, std::string(timed[1].first).c_str());
    why.append(ratio).append(" on this device");
  } else {
    why.append("the only backend timed");
  }
  if (!untimed.empty()) why.append("; the calibration could not time ").append(untimed);
  return {IntervalBackend{timed[0].first}, why.append(" (").append(measured).append(")")};
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
  const auto best_of = [&](IntervalBackend backend) {
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
  for (const volume::VolumeBackendInfo* b : volume::volume_backend_table())
    if (b->gpu() && volume::device_problem(*b, device.capabilities()).empty()) c.ms[std::string(b->name)] = best_of(IntervalBackend{b->name});
  return c;
}

}  // namespace prismoid::frame
