#include "app/volume_options.hpp"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>

#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "app/grid_dataset.hpp"
#include "app/terminal_progress.hpp"
#include "io/image_volume_io.hpp"
#include "io/surface_io.hpp"
#include "io/transfer_function_io.hpp"
#include "io/vdb_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

// The field of a field:NAME[:N] or grid:NAME[:N] dataset, if that is what the command line names.
std::optional<volume::AnalyticField> field_of(const ParsedArgs& a) {
  if (a.files.size() == 1 && is_grid_spec(a.files.front())) return volume::grid_field(grid_from_spec(a.files.front()));
  // A .vdb grid is marched inside its active regions by the march modes, and the reference is
  // its own trilinear field (what the grid means); the other modes draw its voxel tetrahedra
  // (exact linear interpolation of the same samples).
  if (a.files.size() == 1 && io::is_vdb_path(a.files.front()) && a.has("mode") &&
      (a.values.at("mode").rfind("interval-march", 0) == 0 || a.values.at("mode") == "reference")) {
    io::VdbReadOptions vdb;
    if (a.has("grid")) vdb.grid = a.values.at("grid");
    if (a.has("subsample")) vdb.subsample = std::max(1u, parse_uint("subsample", a.values.at("subsample")));
    return volume::grid_field(grid_from_vdb(a.files.front(), vdb));
  }
  if (a.files.size() != 1 || a.files.front().rfind("field:", 0) != 0) return std::nullopt;
  const std::string spec = a.files.front().substr(6);
  return volume::field_from_name(spec.substr(0, spec.find(':')));
}

namespace {

// Loads that took over a second say how long (the "report their time"); quick ones stay quiet.
void report_load_time(const std::string& file, const TetMesh& mesh, std::chrono::steady_clock::time_point start) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (seconds > 1.0)
    std::cerr << "prismoid: loaded " << file << ": " << mesh.tets.size() << " cells in " << std::fixed << std::setprecision(2)
              << seconds << std::defaultfloat << " s\n";
}

}  // namespace

// The dataset named on the command line; the embedded default when none is named.
TetMesh load_scene(const ParsedArgs& a, bool scalar_field) {
  io::TetReadOptions options;
  if (a.has("array")) options.array = a.values.at("array");
  if (a.has("component")) {
    const std::string& c = a.values.at("component");
    if (!a.has("array")) throw InputError("--component", "picks a component of the --array NAME");
    options.component = c == "x" || c == "X" ? 0 : c == "y" || c == "Y" ? 1 : c == "z" || c == "Z" ? 2
                        : c == "magnitude" ? -1 : int(parse_uint("component", c));
  }
  if (scalar_field) options.role = io::ArrayRole::Scalars;
  if (a.has("density-scale")) {
    options.density_scale = parse_double("density-scale", a.values.at("density-scale"));
    if (options.density_scale < 0.0) throw InputError("--density-scale", "must not be negative");
  }
  const bool is_vdb = !a.files.empty() && io::is_vdb_path(a.files.front());
  const bool is_image = !a.files.empty() && io::is_image_volume_path(a.files.front());
  if (a.has("subsample") && !is_image && !is_vdb)
    throw InputError("--subsample", "applies to image volumes (.vti .mhd .mha .inr) and OpenVDB grids (.vdb) only");
  if (a.has("grid") && !is_vdb) throw InputError("--grid", "applies to OpenVDB files (.vdb) only");
  const bool is_surface = !a.files.empty() && io::is_surface_path(a.files.front());
  for (const char* option : {"tetgen-quality", "tetgen-max-volume", "tetgen-cells", "remesh"})
    if (a.has(option) && !is_surface) throw InputError(std::string("--") + option, "applies to surfaces (.vtp .stl .obj .ply .off) only");
  if (a.flags.count("fill-holes") && !is_surface) throw InputError("--fill-holes", "applies to surfaces (.vtp .stl .obj .ply .off) only");
  if (a.files.empty()) {
    if (a.has("array")) throw InputError("--array", "the embedded default dataset has no arrays to choose from");
    TetMesh mesh = make_default_volume();
    if (!scalar_field)
      for (double& s : mesh.cell_extinction) s *= options.density_scale;
    return mesh;
  }
  if (a.files.size() > 1) throw InputError(a.files[1], "several datasets in one scene arrive with the viewer; give one FILE");
  if (const auto field = field_of(a)) {
    if (a.has("array")) throw InputError("--array", "a field:, grid: or marched .vdb dataset has no arrays to choose from");
    if (field->kind == volume::FieldKind::Grid) return grid_dataset_mesh(*field->grid, options.density_scale);
    const std::string& spec = a.files.front();
    uint32_t n = 4;
    if (const auto colon = spec.find(':', 6); colon != std::string::npos) {
      n = parse_uint("field", spec.substr(colon + 1));
      if (n == 0 || n > 128) throw InputError(spec, "the box is split into N^3 cubes with N between 1 and 128 (12.6 million cells)");
    }
    return volume::make_field_mesh(*field, n, options.density_scale);
  }
  const std::string& file = a.files.front();
  if (file.rfind("ball", 0) == 0 && (file.size() == 4 || file[4] == ':')) {  // ball[:S]: the closed-form test volume
    uint32_t subdivisions = 3;
    if (file.size() > 4) {
      subdivisions = parse_uint("ball", file.substr(5));
      if (subdivisions > 7) throw InputError(file, "subdivisions go from 0 (an icosahedron, 20 cells) to 7 (327,680 cells)");
    }
    if (a.has("array")) throw InputError("--array", "the ball has no arrays to choose from");
    return make_ball_mesh(glm::dvec3(0.0), 1.0, subdivisions, options.density_scale);
  }
  if (io::is_surface_path(file)) {  // a closed surface, filled with tetrahedra by TetGen
    if (a.has("array")) throw InputError("--array", file + " is a surface: its tetrahedra carry no arrays");
    io::SurfaceToTets convert;
    convert.fill_holes = a.flags.count("fill-holes") > 0;
    if (a.has("remesh")) {
      convert.remesh_voxel_size = parse_double("remesh", a.values.at("remesh"));
      if (!(convert.remesh_voxel_size > 0.0)) throw InputError("--remesh", "is a voxel size: a positive length");
    }
    if (a.has("tetgen-quality")) convert.tetgen.radius_edge_ratio = parse_double("tetgen-quality", a.values.at("tetgen-quality"));
    if (a.has("tetgen-max-volume")) convert.tetgen.max_volume = parse_double("tetgen-max-volume", a.values.at("tetgen-max-volume"));
    if (a.has("tetgen-cells")) {
      convert.tetgen.target_cells = parse_uint("tetgen-cells", a.values.at("tetgen-cells"));
      if (convert.tetgen.target_cells == 0) throw InputError("--tetgen-cells", "must be at least 1");
    }
    const auto start = std::chrono::steady_clock::now();
    TerminalProgress progress(file);
    convert.progress = progress.callback();
    io::SurfaceTets tets = io::surface_to_tets(file, convert);
    progress.throw_if_cancelled(file);
    TetMesh mesh = std::move(tets.mesh);
    for (double& s : mesh.cell_extinction) s *= options.density_scale;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (tets.from_cache)
      std::cerr << "prismoid: " << file << ": " << mesh.tets.size() << " tetrahedra from the cache (" << tets.cache_file << ") in "
                << seconds << " s\n";
    else
      std::cerr << "prismoid: " << file << ": " << tets.triangles << " triangles -> " << mesh.tets.size()
                << " tetrahedra by TetGen in " << seconds << " s"
                << (convert.tetgen.target_cells ? " (target " + std::to_string(convert.tetgen.target_cells) + ")" : "") << "\n";
    return mesh;
  }
  if (is_vdb) {  // an OpenVDB float grid: voxel tetrahedra, as image volumes
    if (a.has("array")) throw InputError("--array", "picks arrays of meshes and images; a .vdb grid is chosen with --grid NAME");
    if (a.has("component")) throw InputError("--component", "applies to the arrays of .vtu .vtk .vtm .pvtu meshes");
    io::VdbReadOptions vdb;
    if (a.has("grid")) vdb.grid = a.values.at("grid");
    vdb.role = options.role;
    vdb.density_scale = options.density_scale;
    if (a.has("subsample")) {
      vdb.subsample = parse_uint("subsample", a.values.at("subsample"));
      if (vdb.subsample == 0) throw InputError("--subsample", "must be at least 1");
    }
    vdb.max_cells = 50'000'000;  // the image volumes' guard
    TerminalProgress progress(file);
    vdb.progress = progress.callback();
    TetMesh mesh = io::read_vdb_voxels(file, vdb);
    progress.throw_if_cancelled(file);
    return mesh;
  }
  if (a.has("component") && (io::is_image_volume_path(file) || io::is_surface_path(file)))
    throw InputError("--component", "applies to the arrays of .vtu .vtk .vtm .pvtu meshes");
  if (io::is_image_volume_path(file)) {  // voxels: each cell between 8 voxel centres becomes 6 tetrahedra
    io::ImageReadOptions image;
    image.array = options.array;
    image.role = options.role;
    image.density_scale = options.density_scale;
    if (a.has("subsample")) {
      image.subsample = parse_uint("subsample", a.values.at("subsample"));
      if (image.subsample == 0) throw InputError("--subsample", "must be at least 1");
    }
    image.max_cells = 50'000'000;  // about 1.2 GB on the GPU: larger needs --subsample
    const auto start = std::chrono::steady_clock::now();
    TerminalProgress progress(file);
    image.progress = progress.callback();
    TetMesh mesh = io::read_image_volume(file, image);
    progress.throw_if_cancelled(file);
    report_load_time(file, mesh, start);
    return mesh;
  }
  const auto start = std::chrono::steady_clock::now();
  io::MeshConversion conversion;
  io::TetReadOptions reading = options;
  TerminalProgress progress(file);
  reading.progress = progress.callback();
  TetMesh mesh = io::read_tet_mesh(file, reading, &conversion);
  progress.throw_if_cancelled(file);
  if (const std::string note = io::conversion_note(conversion); !note.empty())
    std::cerr << "prismoid: note: " << file << ": " << note << "\n";
  report_load_time(file, mesh, start);
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
                                                 "grid"};

// Parses the volume options, loads the data and builds the frame settings; InputError names
// the option or file at fault.
VolumeChoice volume_choice(const ParsedArgs& a) {
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
  v.mesh = load_scene(a, color);
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
