#include "renderer/volume/volume_backends.hpp"

#include <stdexcept>
#include <string>

#include "renderer/volume/compute/compute_backend.hpp"
#include "renderer/volume/cpu/cpu_backend.hpp"
#include "renderer/volume/mesh/mesh_backend.hpp"

namespace prismoid::volume {

const std::vector<const VolumeBackendInfo*>& volume_backend_table() {
  static const std::vector<const VolumeBackendInfo*> table = {
      &mesh_backend(),
      &compute_backend(),
      &cpu_backend(),
  };
  return table;
}

const VolumeBackendInfo* find_volume_backend(std::string_view name) {
  for (const VolumeBackendInfo* b : volume_backend_table())
    if (b->name == name) return b;
  return nullptr;
}

const VolumeBackendInfo& reference_backend() {
  for (const VolumeBackendInfo* b : volume_backend_table())
    if (!b->gpu()) return *b;
  throw std::logic_error("the volume backend table has no CPU reference");
}

std::string volume_backend_names() {
  std::string names;
  for (const VolumeBackendInfo* b : volume_backend_table()) names += (names.empty() ? "" : ", ") + std::string(b->name);
  return names;
}

std::string missing_features(const std::vector<vk::Feature>& needs, const vk::DeviceCapabilities& caps) {
  std::string missing;
  for (const vk::Feature f : needs)
    if (!vk::has_feature(caps, f)) missing += (missing.empty() ? "" : ", ") + std::string(vk::feature_name(f));
  return missing;
}

std::string device_problem(const VolumeBackendInfo& backend, const vk::DeviceCapabilities& caps) {
  return missing_features(backend.needs, caps);
}

}  // namespace prismoid::volume

namespace prismoid::frame {

FramePlan plan_frame(const SceneContents& scene, const FrameSettings& settings) {
  const volume::VolumeBackendInfo* backend = volume::find_volume_backend(settings.backend.name);
  if (!backend || !backend->gpu())
    throw std::invalid_argument("plan_frame: no GPU volume backend named " + std::string(settings.backend.name));
  return plan_frame(scene, settings, backend->passes);
}

}  // namespace prismoid::frame
