#include "app/common/volume_options.hpp"

#include <algorithm>
#include <iostream>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "app/common/dataset_loader.hpp"
#include "app/common/terminal_progress.hpp"
#include "io/transfer_function_io.hpp"
#include "io/vdb_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

// The field of a field:NAME[:N] or grid:NAME[:N] dataset, if that is what the command line names.
std::optional<volume::AnalyticField> field_of(const ParsedArgs& a) {
  if (a.files.size() != 1) return std::nullopt;
  LoadRequest r;  // only what picks the field: the options are checked when the dataset loads
  r.path = a.files.front();
  r.vdb_marched = io::is_vdb_path(r.path) && a.has("mode") &&
                  (a.values.at("mode").rfind("interval-march", 0) == 0 || a.values.at("mode") == "reference");
  if (a.has("grid")) r.vdb_grid = a.values.at("grid");
  if (a.has("subsample")) r.subsample = std::max(1u, parse_uint("subsample", a.values.at("subsample")));
  return field_of_request(r);
}

// The dataset named on the command line; the embedded default when none is named.
TetMesh load_scene(const ParsedArgs& a, bool scalar_field) {
  const LoadRequest request = load_request_from(a, scalar_field);
  TerminalProgress progress(request.path.empty() ? "default dataset" : request.path);
  TetMesh mesh = load_dataset(request, progress.callback());
  progress.throw_if_cancelled(request.path);
  return mesh;
}

const char* quantity_name(volume::Quantity q) {
  switch (q) {
    case volume::Quantity::OpticalDepth: return "optical-depth";
    case volume::Quantity::Transmittance: return "transmittance";
    case volume::Quantity::Color: return "color";
    case volume::Quantity::Isosurface: return "isosurface";
  }
  return "?";
}

volume::Quantity quantity_of_name(const std::string& q) {
  if (q == "optical-depth") return volume::Quantity::OpticalDepth;
  if (q == "transmittance") return volume::Quantity::Transmittance;
  if (q == "color") return volume::Quantity::Color;
  if (q == "isosurface") return volume::Quantity::Isosurface;
  throw InputError("--quantity", "unknown quantity '" + q + "' (optical-depth, transmittance, color, isosurface)");
}

std::optional<frame::Ordering> ordering_of_mode(const std::string& mode) {
  if (mode == "interval") return frame::Ordering::MeshOrder;
  if (mode == "interval-sorted" || mode == "interval-march") return frame::Ordering::GpuSort;
  if (mode == "interval-exact-order" || mode == "interval-march-exact-order") return frame::Ordering::Exact;
  return std::nullopt;
}

// The transfer function the color options describe, over the data's scalar range unless given.
volume::TransferFunction transfer_from(const ParsedArgs& a, const TetMesh& mesh) {
  volume::TransferFunction tf = io::transfer_function_from(a.has("tf") ? a.values.at("tf") : "cool-to-warm");
  const auto& field = mesh.point_scalars.empty() ? mesh.cell_scalars : mesh.point_scalars;
  if (field.empty())
    throw InputError(mesh.name, "has no scalar field for --quantity color (choose a point or cell array with --array NAME)");
  if (a.has("tf-range")) {
    const std::string& text = a.values.at("tf-range");
    const auto comma = text.find(',');
    if (comma == std::string::npos) throw InputError("--tf-range", "expects LO,HI, got '" + text + "'");
    tf.range_lo = parse_double("tf-range", text.substr(0, comma));
    tf.range_hi = parse_double("tf-range", text.substr(comma + 1));
    if (!(tf.range_hi > tf.range_lo)) throw InputError("--tf-range", "HI must be greater than LO");
  } else {
    const auto [lo, hi] = std::minmax_element(field.begin(), field.end());
    tf.range_lo = *lo;
    tf.range_hi = *hi > *lo ? *hi : *lo + 1.0;  // a constant field still maps somewhere
  }
  tf.density_scale = a.has("density-scale") ? parse_double("density-scale", a.values.at("density-scale")) : 1.0;
  const std::string name = tf.name;
  tf.name = "--tf " + name;
  volume::validate(tf);
  tf.name = name;
  return tf;
}

// The options render and view share: the data, what to show and how.
const std::vector<std::string> kVolumeOptions = {"mode", "quantity", "tf", "tf-range", "preintegration-size", "background",
                                                 "array", "density-scale", "tetlet-size", "march-step", "isovalue",
                                                 "tetgen-quality", "tetgen-max-volume", "tetgen-cells", "remesh", "subsample", "component",
                                                 "grid", "volume-backend"};

// Parses the volume options, loads the data and builds the frame settings; InputError names
// the option or file at fault.
VolumeChoice volume_choice(const ParsedArgs& a, const SceneLoader& load) {
  VolumeChoice v;
  volume::Quantity& quantity = v.quantity;
  if (a.has("quantity")) quantity = quantity_of_name(a.values.at("quantity"));
  const bool color = quantity == volume::Quantity::Color;
  v.mode = a.has("mode") ? a.values.at("mode") : (color ? "interval-sorted" : "interval");
  const std::string& mode = v.mode;
  frame::FrameSettings& settings = v.settings;
  if (const auto ordering = ordering_of_mode(mode)) settings.ordering = *ordering;
  else if (mode != "reference")
    throw InputError("--mode", "unknown mode '" + mode +
                                   "' (available: interval, interval-sorted, interval-exact-order, interval-march, "
                                   "interval-march-exact-order, reference)");
  const bool march = mode.rfind("interval-march", 0) == 0;
  const std::optional<volume::AnalyticField> field = field_of(a);
  if (march && !field)
    throw InputError("--mode " + mode, "marches a field: give a field:NAME or grid:NAME dataset or an OpenVDB .vdb grid (see --help)");
  if (quantity == volume::Quantity::Isosurface && !(field && (march || mode == "reference")))
    throw InputError("--quantity isosurface", "needs a field:NAME or grid:NAME dataset and --mode interval-march or reference");
  if (a.has("isovalue") && quantity != volume::Quantity::Isosurface) throw InputError("--isovalue", "applies to --quantity isosurface only");
  if (a.has("march-step") && !march && mode != "reference")
    throw InputError("--march-step", "applies to --mode interval-march and interval-march-exact-order only");
  if (march && a.has("preintegration-size")) throw InputError("--preintegration-size", "does not apply to interval-march");
  if (!color)
    for (const char* option : {"tf", "tf-range", "preintegration-size", "background"})
      if (a.has(option)) throw InputError(std::string("--") + option, "applies to --quantity color only");
  v.mesh = load(a, color);
  const TetMesh& mesh = v.mesh;
  validate(mesh);
  if (field) {
    volume::MarchSettings& m = settings.resolve.march;
    m.enabled = march;
    m.field = *field;
    const Bounds b = bounds_of(mesh);
    m.step = a.has("march-step") ? parse_double("march-step", a.values.at("march-step")) : glm::length(b.max - b.min) / 100.0;
    if (!(m.step > 0.0)) throw InputError("--march-step", "must be a positive number of world units");
    m.isovalue = a.has("isovalue") ? parse_double("isovalue", a.values.at("isovalue")) : 0.5;
    m.density_scale = a.has("density-scale") ? parse_double("density-scale", a.values.at("density-scale")) : 1.0;
  }

  settings.resolve.quantity = quantity;
  // Which backend draws the intervals: both give the same quantities to the same tolerances.
  const std::string backend = a.has("volume-backend") ? a.values.at("volume-backend") : "mesh";
  if (backend == "mesh") settings.backend = frame::IntervalBackend::Mesh;
  else if (backend == "compute") settings.backend = frame::IntervalBackend::Compute;
  else if (backend == "auto") v.backend_auto = true;
  else throw InputError("--volume-backend", "unknown backend '" + backend + "' (available: mesh, compute, auto)");
  if (a.has("tetlet-size")) settings.resolve.tetlet_size = parse_uint("tetlet-size", a.values.at("tetlet-size"));
  settings.resolve.shared_vertices = a.flags.count("shared-vertices") > 0;
  if (color) {
    settings.resolve.transfer = transfer_from(a, mesh);
    if (a.has("preintegration-size")) settings.resolve.preintegration_size = parse_uint("preintegration-size", a.values.at("preintegration-size"));
    if (a.has("background")) {
      const glm::dvec3 bg = parse_vec3("background", a.values.at("background"));
      if (glm::any(glm::lessThan(bg, glm::dvec3(0.0))) || glm::any(glm::greaterThan(bg, glm::dvec3(1.0))))
        throw InputError("--background", "components must lie in [0, 1]");
      settings.resolve.background = glm::vec3(bg);
    }
    if (mode == "interval")
      std::cerr << "prismoid: note: color is order dependent and --mode interval draws cells in mesh order (approximate); "
                   "interval-sorted or interval-exact-order composite in depth order\n";
  }
  return v;
}

}  // namespace prismoid::app
