#include "renderer/frame/volume_modes.hpp"

#include "renderer/volume/volume_backends.hpp"

namespace prismoid::frame {

const char* volume_backend_name(VolumeBackend backend) {
  switch (backend) {
    case VolumeBackend::Mesh: return "mesh";
    case VolumeBackend::Cpu: return "cpu";
  }
  return "?";
}

const std::vector<VolumeMode>& volume_mode_table() {
  using vk::Feature;
  static const std::vector<VolumeMode> table = {
      {"interval", "interval shading on the GPU, cells in mesh order", VolumeBackend::Mesh, Ordering::MeshOrder, false, false,
       {Feature::MeshShader}},
      {"interval-sorted", "interval shading, cells sorted by centroid distance on the GPU each frame", VolumeBackend::Mesh,
       Ordering::GpuSort, false, false, {Feature::MeshShader}},
      {"interval-exact-order", "interval shading, cells in topological visibility order (exact on convex meshes)",
       VolumeBackend::Mesh, Ordering::Exact, false, false, {Feature::MeshShader}},
      {"interval-march",
       "marching inside intervals: each fragment samples the field of a field:, grid: or .vdb dataset along its interval "
       "(cells sorted on the GPU for color)",
       VolumeBackend::Mesh, Ordering::GpuSort, true, true, {Feature::MeshShader}},
      {"interval-march-exact-order", "marching inside intervals, cells in topological visibility order", VolumeBackend::Mesh,
       Ordering::Exact, true, true, {Feature::MeshShader}},
      {"reference",
       "the CPU, double precision, exact per-pixel order (with a field:, grid: or .vdb dataset, of the field itself)",
       VolumeBackend::Cpu, Ordering::Exact, false, true, {}},
  };
  return table;
}

const VolumeMode* find_volume_mode(std::string_view name) {
  for (const VolumeMode& m : volume_mode_table())
    if (m.name == name) return &m;
  return nullptr;
}

const VolumeMode* find_volume_mode(Ordering ordering, bool march) {
  for (const VolumeMode& m : volume_mode_table())
    if (m.gpu() && m.ordering == ordering && m.march == march) return &m;
  return nullptr;
}

const VolumeMode& default_volume_mode(volume::Quantity quantity) {
  return *find_volume_mode(volume::order_dependent(quantity) ? Ordering::GpuSort : Ordering::MeshOrder, false);
}

std::string volume_mode_names() {
  std::string names;
  for (const VolumeMode& m : volume_mode_table()) names += (names.empty() ? "" : ", ") + std::string(m.name);
  return names;
}

std::string device_problem(const VolumeMode& mode, const vk::DeviceCapabilities& caps) {
  return volume::missing_features(mode.needs, caps);
}

}  // namespace prismoid::frame
