#include "app/common/volume_options.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "app/common/dataset_loader.hpp"
#include "app/common/terminal_progress.hpp"
#include "app/common/volume_option_table.hpp"
#include "io/image_io.hpp"
#include "io/transfer_function_io.hpp"
#include "io/vdb_io.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

// The field of a field:NAME[:N] or grid:NAME[:N] dataset, if that is what the command line names.
std::optional<volume::AnalyticField> field_of(const ParsedArgs& a) {
  if (a.files.size() != 1) return std::nullopt;
  LoadRequest r;  // only what picks the field: the options are checked when the dataset loads
  r.path = a.files.front();
  r.vdb_marched = io::is_vdb_path(r.path) && samples_field(a);
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

const frame::VolumeMode& volume_mode_from(const ParsedArgs& a, volume::Quantity quantity) {
  if (!a.has("mode")) return frame::default_volume_mode(quantity);
  const std::string& name = a.values.at("mode");
  const frame::VolumeMode* mode = frame::find_volume_mode(name);
  if (!mode) throw InputError("--mode", "unknown mode '" + name + "' (available: " + frame::volume_mode_names() + ")");
  return *mode;
}

ColourLook default_colour_look(const TetMesh& mesh) {
  ColourLook look;
  const auto& field = mesh.point_scalars.empty() ? mesh.cell_scalars : mesh.point_scalars;
  if (!field.empty()) {
    const auto [lo, hi] = std::minmax_element(field.begin(), field.end());
    std::vector<double> sorted(field.begin(), field.end());
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    if (*hi > *lo) look.opacity_from = std::clamp((median - *lo) / (*hi - *lo), kLowestHidden, kMostHidden);
  }
  const Bounds b = bounds_of(mesh);
  const double diagonal = glm::length(b.max - b.min);
  if (diagonal > 0.0 && std::isfinite(diagonal)) look.density_scale = kDiagonalOpticalDepth / diagonal;
  return look;
}

// The transfer function the color options describe, over the data's scalar range unless given.
volume::TransferFunction transfer_from(const ParsedArgs& a, const TetMesh& mesh) {
  // Only what is not given is worked out (the median sorts a copy of the field).
  const ColourLook look = a.has("tf") && a.has("density-scale") ? ColourLook{} : default_colour_look(mesh);
  volume::TransferFunction tf = io::transfer_function_from(a.has("tf") ? a.values.at("tf") : std::string(kDefaultColourMap));
  if (!a.has("tf")) {
    tf.opacity = {{0.0, 0.0}, {look.opacity_from, 0.0}, {1.0, 1.0}};
    // append rather than +: GCC 12 warns falsely (-Warray-bounds) about + here.
    tf.name = std::string(kDefaultColourMap).append(", opacity from the field's median");
  }
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
  tf.density_scale = a.has("density-scale") ? parse_double("density-scale", a.values.at("density-scale")) : look.density_scale;
  const std::string name = tf.name;
  tf.name = "--tf " + name;
  volume::validate(tf);
  tf.name = name;
  return tf;
}

// The options render and view share, from the option table: the data, what to show and how.
const std::vector<std::string> kVolumeOptions = volume_value_options();

// Parses the volume options, loads the data and builds the frame settings; InputError names
// the option or file at fault.
VolumeChoice volume_choice(const ParsedArgs& a, const SceneLoader& load) {
  VolumeChoice v;
  volume::Quantity& quantity = v.quantity;
  // The embedded default dataset, asked for nothing in particular, shows what Prismoid is for:
  // its smooth density's colour, composited in exact order. Files keep transmittance unless told.
  const bool first_look = a.files.empty() && !a.has("quantity") && !a.has("mode");
  if (a.has("quantity")) quantity = quantity_of_name(a.values.at("quantity"));
  else if (first_look) quantity = volume::Quantity::Color;
  const bool color = quantity == volume::Quantity::Color;
  // Which backend draws the volume (the table's, or auto): every one gives the same quantities
  // to its tolerances. The CPU one draws what the reference mode does.
  const std::string backend = a.has("volume-backend") ? a.values.at("volume-backend") : "mesh";
  const volume::VolumeBackendInfo* drawn_by = volume::find_volume_backend(backend);
  if (backend == "auto") v.backend_auto = true;
  else if (!drawn_by)
    throw InputError("--volume-backend", "unknown backend '" + backend + "' (available: " + volume::volume_backend_names() + ", auto)");
  if (drawn_by && !drawn_by->gpu()) {
    const frame::VolumeMode* cpu_mode = nullptr;
    for (const frame::VolumeMode& m : frame::volume_mode_table())
      if (!m.gpu()) cpu_mode = &m;
    if (a.has("mode") && a.values.at("mode") != cpu_mode->name)
      throw InputError("--volume-backend " + backend, "draws the CPU reference: --mode " + a.values.at("mode") + " is drawn on the GPU");
    v.mode = cpu_mode;
  } else {
    v.mode = first_look ? frame::find_volume_mode(frame::Ordering::Exact, false) : &volume_mode_from(a, quantity);
  }
  const frame::VolumeMode& mode = *v.mode;
  const std::string name(mode.name);
  frame::FrameSettings& settings = v.settings;
  settings.ordering = mode.ordering;
  const bool march = mode.march;
  const std::optional<volume::AnalyticField> field = field_of(a);
  if (march && !field)
    throw InputError("--mode " + name, "marches a field: give a field:NAME or grid:NAME dataset or an OpenVDB .vdb grid (see --help)");
  // The modes an option applies to, named from the table.
  const auto modes_that = [](bool (*pick)(const frame::VolumeMode&)) {
    std::string names;
    for (const frame::VolumeMode& m : frame::volume_mode_table())
      if (pick(m)) names += (names.empty() ? "" : ", ") + std::string(m.name);
    return names;
  };
  const auto sampling = [](const frame::VolumeMode& m) { return m.samples_field; };
  if (quantity == volume::Quantity::Isosurface && !(field && mode.samples_field))
    throw InputError("--quantity isosurface", "needs a field:NAME or grid:NAME dataset and --mode " + modes_that(sampling));
  if (a.has("isovalue") && quantity != volume::Quantity::Isosurface) throw InputError("--isovalue", "applies to --quantity isosurface only");
  if (a.has("march-step") && !mode.samples_field) throw InputError("--march-step", "applies to --mode " + modes_that(sampling) + " only");
  if (march && a.has("preintegration-size")) throw InputError("--preintegration-size", "does not apply to --mode " + name);
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
  if (drawn_by && drawn_by->gpu()) settings.backend = frame::IntervalBackend{drawn_by->name};
  if (a.has("tetlet-size")) settings.resolve.tetlet_size = parse_uint("tetlet-size", a.values.at("tetlet-size"));
  settings.resolve.shared_vertices = a.flags.count("shared-vertices") > 0;
  if (color) {
    settings.resolve.transfer = transfer_from(a, mesh);
    if (a.has("preintegration-size")) settings.resolve.preintegration_size = parse_uint("preintegration-size", a.values.at("preintegration-size"));
    settings.resolve.background = kDefaultColourBackground;
    if (a.has("background")) {
      const glm::dvec3 bg = parse_vec3("background", a.values.at("background"));
      if (glm::any(glm::lessThan(bg, glm::dvec3(0.0))) || glm::any(glm::greaterThan(bg, glm::dvec3(1.0))))
        throw InputError("--background", "components must lie in [0, 1]");
      settings.resolve.background = glm::vec3(bg);
    }
    // The compute backend orders each pixel itself, exactly: mesh order is the mesh backend's.
    if (mode.gpu() && mode.ordering == frame::Ordering::MeshOrder && settings.backend == frame::IntervalBackend::Mesh &&
        !v.backend_auto) {
      const auto ordered = [](const frame::VolumeMode& m) { return m.gpu() && !m.march && m.ordering != frame::Ordering::MeshOrder; };
      std::cerr << "prismoid: note: color is order dependent and --mode " << name
                << " draws cells in mesh order (approximate); " << modes_that(ordered) << " composite in depth order\n";
    }
  }
  return v;
}

// --depth-limit FILE.pfm: one value per pixel of the frame, the depth along the viewing axis
// where the ray ends (opaque geometry), +inf where nothing is; row 0 at the top as the image's.
std::shared_ptr<const std::vector<float>> read_depth_limit(const std::string& path, VkExtent2D size) {
  const io::FloatImage image = io::read_pfm(path);
  if (image.channels != 1) throw InputError(path, "--depth-limit wants one value per pixel (a grey PFM), not " + std::to_string(image.channels));
  if (image.width != size.width || image.height != size.height)
    throw InputError(path, "is " + std::to_string(image.width) + "x" + std::to_string(image.height) + "; the frame (--size) is " +
                               std::to_string(size.width) + "x" + std::to_string(size.height));
  for (float d : image.pixels)
    if (!(d > 0.0f)) throw InputError(path, "holds a depth that is not positive (or NaN): depths along the viewing axis are > 0, +inf for none");
  return std::make_shared<const std::vector<float>>(image.pixels);
}

}  // namespace prismoid::app
