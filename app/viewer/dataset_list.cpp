#include "app/viewer/dataset_list.hpp"

#include <algorithm>

#include "app/common/volume_options.hpp"
#include "app/viewer/scene_merge.hpp"
#include "renderer/frame/volume_modes.hpp"

namespace prismoid::app {

namespace {

// After the scene changed: the mode and quantity it can still show. Marching needs the one
// field dataset, so a march mode falls back to the same ordering without marching.
std::string fit_mode_to_scene(ViewState& state) {
  const std::string mode_before = state.mode;
  const volume::Quantity quantity_before = state.settings.resolve.quantity;
  if (!set_mode(state, state.mode).empty()) {
    const frame::VolumeMode* mode = frame::find_volume_mode(state.mode);
    const frame::VolumeMode* unmarched = frame::find_volume_mode(mode ? mode->ordering : frame::Ordering::GpuSort, false);
    set_mode(state, std::string(unmarched->name));
  }
  std::string note;
  if (state.mode != mode_before) note = "mode " + mode_before + " does not apply to " + state.drawn().name + ": now " + state.mode;
  if (state.settings.resolve.quantity != quantity_before)
    note += std::string(note.empty() ? "" : "; ") + quantity_name(quantity_before) + " is not available for " + state.drawn().name +
            ": showing " + quantity_name(state.settings.resolve.quantity);
  return note;
}

void use_range_of(ViewState& state, const Dataset& d) {
  if (!d.has_scalars) return;
  state.settings.resolve.transfer.range_lo = d.scalar_lo;
  state.settings.resolve.transfer.range_hi = d.scalar_hi;
}

}  // namespace

void rebuild_scene(ViewState& state) {
  std::vector<const Dataset*> visible;
  for (const Dataset& d : state.datasets)
    if (d.visible) visible.push_back(&d);
  if (visible.size() == 1) {
    state.scene = *visible.front();
    return;
  }
  std::vector<const TetMesh*> meshes;
  for (const Dataset* d : visible) meshes.push_back(d->mesh.get());
  state.scene = make_dataset(merge_meshes(meshes));
}

std::string add_dataset(ViewState& state, Dataset dataset) {
  dataset.visible = true;
  state.datasets.push_back(std::move(dataset));
  state.active = state.datasets.size() - 1;
  use_range_of(state, state.datasets.back());
  rebuild_scene(state);
  return fit_mode_to_scene(state);
}

std::string show_dataset(ViewState& state, size_t index, bool visible) {
  if (index >= state.datasets.size()) return "show: there is no dataset " + std::to_string(index);
  Dataset& d = state.datasets[index];
  if (d.visible == visible) return {};
  const auto shown = std::count_if(state.datasets.begin(), state.datasets.end(), [](const Dataset& x) { return x.visible; });
  if (!visible && shown == 1) return "show: " + d.name + " is the only dataset shown; show another first";
  d.visible = visible;
  rebuild_scene(state);
  return fit_mode_to_scene(state);
}

std::string set_active(ViewState& state, size_t index) {
  if (index >= state.datasets.size()) return "active: there is no dataset " + std::to_string(index);
  state.active = index;
  use_range_of(state, state.datasets[index]);
  return {};
}

std::string show_step(ViewState& state, size_t index, Dataset step) {
  if (index >= state.datasets.size()) return "time-step: there is no dataset " + std::to_string(index);
  step.visible = state.datasets[index].visible;
  state.datasets[index] = std::move(step);
  if (index == state.active && state.range_per_step) use_range_of(state, state.datasets[index]);
  rebuild_scene(state);
  return fit_mode_to_scene(state);
}

}  // namespace prismoid::app
