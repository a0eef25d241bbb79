#pragma once
// The volume modes: one table from which `render` and `view` parse --mode and list the modes in
// their help, the window fills its mode menu, the bench sweeps, and `devices` says which modes a
// device draws. A mode is a line of the table: which backend draws it, the order its cells are
// drawn in, whether it marches a field inside the intervals, and what its backend needs from the
// device. Mode names appear nowhere else but in tests; code that needs a particular mode asks the
// table by its properties (find_volume_mode(ordering, march), default_volume_mode).
#include <string>
#include <string_view>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/vk/capabilities.hpp"

namespace prismoid::frame {

// What draws a mode's frames.
enum class VolumeBackend {
  Mesh,  // interval shading (renderer/volume): a mesh-shader workgroup emits each cell's proxy
  Cpu,   // the CPU double-precision reference (renderer/reference): not in the window or the bench
};
// "mesh", "cpu".
const char* volume_backend_name(VolumeBackend backend);

struct VolumeMode {
  std::string_view name;
  std::string_view summary;  // one line for the help text and the window's menu
  VolumeBackend backend = VolumeBackend::Mesh;
  Ordering ordering = Ordering::MeshOrder;  // the cells' draw order (the CPU reference: exact per pixel)
  bool march = false;  // samples a field inside each interval: needs a field (field:, grid:, .vdb)
  // Reads the field itself where the dataset has one (the march modes and the reference): then
  // --march-step and --quantity isosurface apply, and a .vdb loads as its active regions.
  bool samples_field = false;
  std::vector<vk::Feature> needs;  // what its backend needs from the device
  bool gpu() const { return backend != VolumeBackend::Cpu; }
};

// Every volume mode, in the order the help and the window list them (GPU modes first).
const std::vector<VolumeMode>& volume_mode_table();
// The mode of that name; nullptr for a name that is not a volume mode.
const VolumeMode* find_volume_mode(std::string_view name);
// The GPU mode that draws cells in `ordering` and marches or not; nullptr when none does.
const VolumeMode* find_volume_mode(Ordering ordering, bool march);
// The mode when --mode is not given: mesh order for order-independent quantities, where the
// order changes nothing and costs nothing; the GPU sort for colour.
const VolumeMode& default_volume_mode(volume::Quantity quantity);
// Every name, ", "-separated, for messages.
std::string volume_mode_names();
// What `caps` lacks for the mode ("mesh shader, ..."); empty when it can draw it.
std::string device_problem(const VolumeMode& mode, const vk::DeviceCapabilities& caps);

}  // namespace prismoid::frame
