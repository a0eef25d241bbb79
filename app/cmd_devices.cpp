// `prismoid devices`: what each Vulkan device can run.
#include <iostream>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/cli_args.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"

namespace prismoid::app {

const char* const kDevicesHelp =
    "usage: prismoid devices [--validate]\n"
    "\n"
    "Lists every Vulkan device with its driver, the features Prismoid's modes use (yes/no), and\n"
    "which device `render` and `view` would choose.\n";

int cmd_devices(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, {}, {"validate", "help"});
  if (a.flags.count("help")) { std::cout << kDevicesHelp; return kOk; }
  vk::Instance instance({.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  auto yn = [](bool b) { return b ? "yes" : "no"; };
  if (devices.empty()) { std::cout << "no Vulkan devices found\n"; return kNoDevice; }
  for (const auto& d : devices) {
    std::cout << "device " << d.index << ": " << d.name << "\n"
              << "  type: " << d.type << ", Vulkan " << vk::version_string(d.api_version) << "\n"
              << "  driver: " << d.driver_name << " (" << d.driver_info << ")\n"
              << "  device-local memory: " << (d.device_local_bytes >> 20) << " MiB\n"
              << "  mesh shader: " << yn(d.mesh_shader) << " (task shader: " << yn(d.task_shader)
              << ", max outputs " << d.max_mesh_output_vertices << " vertices / " << d.max_mesh_output_primitives << " primitives)\n"
              << "  ray-tracing pipeline: " << yn(d.ray_tracing_pipeline) << "\n"
              << "  acceleration structures: " << yn(d.acceleration_structure) << "\n"
              << "  ray query: " << yn(d.ray_query) << "\n"
              << "  timestamps: " << yn(d.timestamps) << " (" << d.timestamp_period_ns << " ns/tick)\n"
              << "  presentation (swapchain): " << yn(d.swapchain) << "\n"
              << "  modes:\n";
    for (const auto& m : vk::mode_requirements()) {
      std::string missing;
      for (auto f : m.required)
        if (!vk::has_feature(d, f)) missing += std::string(missing.empty() ? "" : ", ") + vk::feature_name(f);
      std::cout << "    " << m.mode << ": " << (missing.empty() ? "yes" : "no (needs " + missing + ")") << "\n";
    }
    std::string volume_modes;
    for (const frame::VolumeMode& m : frame::volume_mode_table())
      if (m.gpu() && frame::device_problem(m, d).empty()) volume_modes += (volume_modes.empty() ? "" : ", ") + std::string(m.name);
    std::cout << "  volume modes it draws: " << (volume_modes.empty() ? "none" : volume_modes) << "\n";
    std::string backends;
    for (const volume::VolumeBackendInfo* b : volume::volume_backend_table()) {
      if (!b->gpu()) continue;
      const std::string missing = volume::device_problem(*b, d);
      backends.append(backends.empty() ? "" : ", ").append(b->name).append(missing.empty() ? "" : " (no: needs " + missing + ")");
    }
    std::cout << "  volume backends: " << backends << "\n";
  }
  try {
    const auto& chosen = vk::select_device(devices, std::nullopt);
    std::cout << "default choice: device " << chosen.index << " (" << chosen.name << ")\n";
  } catch (const vk::NoSuitableDevice& e) {
    std::cout << "default choice: none: " << e.what() << "\n";
  }
  return validation_exit(instance);
}

}  // namespace prismoid::app
