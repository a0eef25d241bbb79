#include "app/viewer/view_state.hpp"

#include <algorithm>
#include <glm/geometric.hpp>

#include "app/common/volume_options.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

Dataset make_dataset(TetMesh mesh, std::optional<volume::AnalyticField> field) {
  Dataset d;
  d.name = mesh.name;
  d.bounds = bounds_of(mesh);
  d.field = std::move(field);
  const auto& scalars = mesh.point_scalars.empty() ? mesh.cell_scalars : mesh.point_scalars;
  d.has_scalars = !scalars.empty();
  if (d.has_scalars) {
    const auto [lo, hi] = std::minmax_element(scalars.begin(), scalars.end());
    d.scalar_lo = *lo;
    d.scalar_hi = *hi > *lo ? *hi : *lo + 1.0;
  }
  d.mesh = std::make_shared<const TetMesh>(std::move(mesh));
  return d;
}

void attach_time(Dataset& d, const LoadRequest& request) {
  d.times = time_values(request.path);
  if (d.times.empty()) return;
  d.source = request;
  d.step = step_of_request(request, d.times);
}

std::vector<std::string> modes_for(const Dataset& dataset) {
  std::vector<std::string> modes;
  for (const frame::VolumeMode& m : frame::volume_mode_table())
    if (m.gpu() && (!m.march || dataset.field)) modes.emplace_back(m.name);
  return modes;
}

std::vector<volume::Quantity> quantities_for(const Dataset& dataset, const std::string& mode) {
  const frame::VolumeMode* m = frame::find_volume_mode(mode);
  const bool march = m && m->march;
  std::vector<volume::Quantity> q = {volume::Quantity::OpticalDepth, volume::Quantity::Transmittance};
  if (dataset.has_scalars || march) q.push_back(volume::Quantity::Color);
  if (march) q.push_back(volume::Quantity::Isosurface);
  return q;
}

namespace {

bool contains(const std::vector<volume::Quantity>& list, volume::Quantity q) {
  return std::find(list.begin(), list.end(), q) != list.end();
}

}  // namespace

std::string set_mode(ViewState& state, const std::string& mode) {
  const auto modes = modes_for(state.drawn());
  if (std::find(modes.begin(), modes.end(), mode) == modes.end())
    return "mode '" + mode + "' is not available for " + state.drawn().name;
  const frame::VolumeMode& row = *frame::find_volume_mode(mode);  // modes_for lists only the table's
  state.mode = mode;
  state.settings.ordering = row.ordering;
  const bool march = row.march;
  volume::MarchSettings& m = state.settings.resolve.march;
  m.enabled = march;
  if (state.drawn().field) {
    m.field = *state.drawn().field;
    if (!(m.step > 0.0)) m.step = glm::length(state.drawn().bounds.max - state.drawn().bounds.min) / 100.0;
  }
  // A quantity the new mode cannot show falls back to the first one it can.
  const auto quantities = quantities_for(state.drawn(), mode);
  if (!contains(quantities, state.settings.resolve.quantity)) state.settings.resolve.quantity = quantities.front();
  if (!shared_vertices_problem(state).empty()) state.settings.resolve.shared_vertices = false;
  return {};
}

std::string set_quantity(ViewState& state, volume::Quantity quantity) {
  if (!contains(quantities_for(state.drawn(), state.mode), quantity))
    return std::string("quantity '") + quantity_name(quantity) + "' is not available in mode " + state.mode;
  state.settings.resolve.quantity = quantity;
  if (!shared_vertices_problem(state).empty()) state.settings.resolve.shared_vertices = false;
  return {};
}

std::string set_preset(ViewState& state, const std::string& preset_name) {
  const auto names = volume::preset_names();
  if (std::find(names.begin(), names.end(), preset_name) == names.end()) return "no transfer-function preset '" + preset_name + "'";
  volume::TransferFunction& tf = state.settings.resolve.transfer;
  volume::TransferFunction next = volume::preset(preset_name);
  next.range_lo = tf.range_lo;
  next.range_hi = tf.range_hi;
  next.density_scale = tf.density_scale;
  tf = std::move(next);
  state.tf_preset = preset_name;
  return {};
}

std::string shared_vertices_problem(const ViewState& state) {
  if (state.settings.resolve.tetlet_size < 2) return "needs a tetlet size above 1";
  if (volume::order_dependent(state.settings.resolve.quantity) && state.settings.ordering != frame::Ordering::MeshOrder)
    return "tetlets fix the draw order: not with colour in a sorted mode";
  return {};
}

}  // namespace prismoid::app
