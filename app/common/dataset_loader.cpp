#include "app/common/dataset_loader.hpp"

#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/common/grid_dataset.hpp"
#include "io/image_volume_io.hpp"
#include "io/exodus_io.hpp"
#include "io/time_series.hpp"
#include "io/vdb_io.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::app {

namespace {

const char* const kSurfaceKinds = "applies to surfaces (.vtp .stl .obj .ply .off) only";

bool is_ball_spec(const std::string& path) { return path.rfind("ball", 0) == 0 && (path.size() == 4 || path[4] == ':'); }

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Loads that took over a second say how long (the "report their time"); quick ones stay quiet.
void report_load_time(const std::string& file, const TetMesh& mesh, std::chrono::steady_clock::time_point start) {
  const double seconds = seconds_since(start);
  if (seconds > 1.0) {
    std::ostringstream line;
    line << "prismoid: loaded " << file << ": " << mesh.tets.size() << " cells in " << std::fixed << std::setprecision(2) << seconds
         << " s\n";
    std::cerr << line.str();  // one write: a loader thread's line does not interleave with others
  }
}

TetMesh load_default(const LoadRequest& r) {
  if (!r.array.empty()) throw InputError("--array", "the embedded default dataset has no arrays to choose from");
  TetMesh mesh = make_default_volume();
  if (r.role == io::ArrayRole::Extinction)
    for (double& s : mesh.cell_extinction) s *= r.density_scale;
  return mesh;
}

TetMesh load_field(const LoadRequest& r, const volume::AnalyticField& field) {
  if (!r.array.empty()) throw InputError("--array", "a field:, grid: or marched .vdb dataset has no arrays to choose from");
  if (field.kind == volume::FieldKind::Grid) return grid_dataset_mesh(*field.grid, r.density_scale);
  uint32_t n = 4;
  if (const auto colon = r.path.find(':', 6); colon != std::string::npos) {
    n = parse_uint("field", r.path.substr(colon + 1));
    if (n == 0 || n > 128) throw InputError(r.path, "the box is split into N^3 cubes with N between 1 and 128 (12.6 million cells)");
  }
  return volume::make_field_mesh(field, n, r.density_scale);
}

TetMesh load_ball(const LoadRequest& r) {  // ball[:S]: the closed-form test volume
  uint32_t subdivisions = 3;
  if (r.path.size() > 4) {
    subdivisions = parse_uint("ball", r.path.substr(5));
    if (subdivisions > 7) throw InputError(r.path, "subdivisions go from 0 (an icosahedron, 20 cells) to 7 (327,680 cells)");
  }
  if (!r.array.empty()) throw InputError("--array", "the ball has no arrays to choose from");
  return make_ball_mesh(glm::dvec3(0.0), 1.0, subdivisions, r.density_scale);
}

TetMesh load_surface(const LoadRequest& r, const io::Progress& progress) {  // filled with tetrahedra by TetGen
  if (!r.array.empty()) throw InputError("--array", r.path + " is a surface: its tetrahedra carry no arrays");
  if (r.component) throw InputError("--component", "applies to the arrays of .vtu .vtk .vtm .pvtu meshes");
  io::SurfaceToTets convert;
  convert.fill_holes = r.fill_holes;
  convert.tetgen = r.tetgen;
  convert.remesh_voxel_size = r.remesh_voxel_size;
  convert.progress = progress;
  const auto start = std::chrono::steady_clock::now();
  io::SurfaceTets tets = io::surface_to_tets(r.path, convert);
  TetMesh mesh = std::move(tets.mesh);
  for (double& s : mesh.cell_extinction) s *= r.density_scale;
  std::ostringstream line;
  if (tets.from_cache)
    line << "prismoid: " << r.path << ": " << mesh.tets.size() << " tetrahedra from the cache (" << tets.cache_file << ") in "
         << seconds_since(start) << " s\n";
  else
    line << "prismoid: " << r.path << ": " << tets.triangles << " triangles -> " << mesh.tets.size() << " tetrahedra by TetGen in "
         << seconds_since(start) << " s"
         << (r.tetgen.target_cells ? " (target " + std::to_string(r.tetgen.target_cells) + ")" : "") << "\n";
  std::cerr << line.str();
  return mesh;
}

// Grids (OpenVDB and image volumes) become voxel tetrahedra the same way: their readers take the
// same options from the request, and are timed alike.
template <typename Options, typename Read>
TetMesh load_grid(const LoadRequest& r, const io::Progress& progress, Options options, Read read) {
  if (r.component) throw InputError("--component", "applies to the arrays of .vtu .vtk .vtm .pvtu meshes");
  options.role = r.role;
  options.density_scale = r.density_scale;
  options.subsample = r.subsample.value_or(1);
  options.max_cells = io::kInteractiveMaxCells;
  options.progress = progress;
  const auto start = std::chrono::steady_clock::now();
  TetMesh mesh = read(r.path, options);
  report_load_time(r.path, mesh, start);
  return mesh;
}

TetMesh load_vdb(const LoadRequest& r, const io::Progress& progress) {  // an OpenVDB float grid: voxel tetrahedra, as image volumes
  if (!r.array.empty()) throw InputError("--array", "picks arrays of meshes and images; a .vdb grid is chosen with --grid NAME");
  io::VdbReadOptions vdb;
  vdb.grid = r.vdb_grid;
  return load_grid(r, progress, vdb, [](const std::string& path, const io::VdbReadOptions& o) { return io::read_vdb_voxels(path, o); });
}

TetMesh load_image(const LoadRequest& r, const io::Progress& progress) {  // each voxel cell becomes 6 tetrahedra
  io::ImageReadOptions image;
  image.array = r.array;
  return load_grid(r, progress, image, [](const std::string& path, const io::ImageReadOptions& o) { return io::read_image_volume(path, o); });
}

// .vtu .vtk .vtm .pvtu and Exodus II through VTK; `conversion` (where given) receives what reading
// it did. `time_step`: an Exodus file's.
TetMesh load_unstructured(const LoadRequest& r, const io::Progress& progress, io::MeshConversion* conversion_out = nullptr,
                          uint32_t time_step = 0) {
  io::TetReadOptions reading;
  reading.blocks = r.blocks;
  reading.time_step = time_step;
  reading.subdivision = r.subdivision;
  reading.array = r.array;
  reading.component = r.component.value_or(-1);
  reading.role = r.role;
  reading.density_scale = r.density_scale;
  reading.progress = progress;
  const auto start = std::chrono::steady_clock::now();
  io::MeshConversion conversion;
  TetMesh mesh = io::read_tet_mesh(r.path, reading, &conversion);
  if (const std::string note = io::conversion_note(conversion); !note.empty())
    std::cerr << "prismoid: note: " + r.path + ": " + note + "\n";
  if (!conversion.chosen_array.empty())
    std::cerr << "prismoid: note: " + r.path + ": the scalar field is " + conversion.chosen_why + ", '" + conversion.chosen_array +
                     "' (--array NAME picks another)\n";
  report_load_time(r.path, mesh, start);
  if (conversion_out) *conversion_out = conversion;
  return mesh;
}

// One step of a time series (.pvd): its mesh read as any mesh file is, named by the series, the
// step and its time.
TetMesh load_time_step(const LoadRequest& r, const io::Progress& progress) {
  const io::TimeSeries series = io::read_time_series(r.path);
  const size_t i = io::pick_time_step(series, r.path, r.time_step, r.time);
  const io::TimeStep& step = series.steps[i];
  if (!r.time_step && !r.time && series.steps.size() > 1)
    std::cerr << "prismoid: note: " << r.path << ": a time series of " << series.steps.size() << " steps; drawing step 0 (t = "
              << json_number(step.time) << "): --time-step N or --time T picks another (`prismoid info` lists them)\n";
  LoadRequest one = r;
  one.path = step.file;
  io::MeshConversion conversion;
  TetMesh mesh = load_unstructured(one, progress, &conversion);
  // The steps of a series colour by one quantity: an array chosen by rule (no --array) must be the
  // one step 0 is coloured by, or a step would be silently coloured by another. Step 0 is read
  // again for its choice; --array spares that read (each step must then hold the array).
  if (i > 0 && r.array.empty() && r.role == io::ArrayRole::Scalars) {
    io::TetReadOptions reading;
    reading.role = io::ArrayRole::Scalars;
    io::MeshConversion first;
    io::read_tet_mesh(series.steps.front().file, reading, &first);
    const auto named = [](const std::string& a) { return a.empty() ? std::string("no array") : "'" + a + "'"; };
    if (first.chosen_array != conversion.chosen_array)
      throw InputError(r.path, "step " + std::to_string(i) + " would be coloured by " + named(conversion.chosen_array) + " and step 0 by " +
                                   named(first.chosen_array) + ": the steps' arrays differ; name the array with --array");
  }
  mesh.name = r.path + " step " + std::to_string(i) + " (t = " + json_number(step.time) + ")";
  return mesh;
}

// --blocks' comma-separated ids or names (spaces around each dropped; none may be empty).
std::vector<std::string> block_list(const std::string& text) {
  std::vector<std::string> blocks;
  size_t start = 0;
  while (true) {
    const size_t comma = std::min(text.find(',', start), text.size());
    std::string token = text.substr(start, comma - start);
    token.erase(0, token.find_first_not_of(' '));
    token.erase(token.find_last_not_of(' ') + 1);
    if (token.empty()) throw InputError("--blocks", "'" + text + "' holds an empty block name; give ids or names separated by commas");
    blocks.push_back(token);
    if (comma == text.size()) return blocks;
    start = comma + 1;
  }
}

// An Exodus II file: its step picked as a time series' is (the file's time values), its blocks as
// asked. Exodus variables are the file's, the same at every step: no step is coloured by another.
TetMesh load_exodus(const LoadRequest& r, const io::Progress& progress) {
  const io::ExodusInfo info = io::read_exodus_info(r.path, /*cells=*/false);
  io::TimeSeries steps;
  for (double t : info.times) steps.steps.push_back({t, r.path});
  if (steps.steps.empty() && (r.time_step || r.time))
    throw InputError(r.time_step ? "--time-step" : "--time", r.path + " holds no time steps (one state, drawn as it is)");
  const size_t i = steps.steps.empty() ? 0 : io::pick_time_step(steps, r.path, r.time_step, r.time);
  if (!r.time_step && !r.time && steps.steps.size() > 1)
    std::cerr << "prismoid: note: " << r.path << ": " << steps.steps.size() << " time steps; drawing step 0 (t = " << json_number(info.times[0])
              << "): --time-step N or --time T picks another (`prismoid info` lists them)\n";
  TetMesh mesh = load_unstructured(r, progress, nullptr, uint32_t(i));
  if (!steps.steps.empty()) mesh.name = r.path + " step " + std::to_string(i) + " (t = " + json_number(info.times[i]) + ")";
  return mesh;
}

}  // namespace

std::vector<double> time_values(const std::string& path) {
  std::vector<double> times;
  if (path.empty() || path.rfind("field:", 0) == 0 || path.rfind("grid:", 0) == 0) return times;
  if (io::is_time_series_path(path))
    for (const io::TimeStep& step : io::read_time_series(path).steps) times.push_back(step.time);
  else if (io::is_exodus_path(path))
    times = io::read_exodus_info(path, /*cells=*/false).times;
  return times;
}

uint32_t step_of_request(const LoadRequest& request, const std::vector<double>& times) {
  if (times.empty()) return 0;
  io::TimeSeries series;
  for (double t : times) series.steps.push_back({t, request.path});
  return uint32_t(io::pick_time_step(series, request.path, request.time_step, request.time));
}

std::optional<volume::AnalyticField> field_of_request(const LoadRequest& r) {
  // A .vdb grid is marched inside its active regions by the march modes, and the reference is
  // its own trilinear field (what the grid means); the other modes draw its voxel tetrahedra
  // (exact linear interpolation of the same samples).
  if (r.vdb_marched) {
    io::VdbReadOptions vdb;
    vdb.grid = r.vdb_grid;
    vdb.subsample = r.subsample.value_or(1);
    return volume::grid_field(grid_from_vdb(r.path, vdb));
  }
  return field_of_path(r.path);
}

std::optional<volume::AnalyticField> field_of_path(const std::string& path) {
  if (is_grid_spec(path)) return volume::grid_field(grid_from_spec(path));
  if (path.rfind("field:", 0) != 0) return std::nullopt;
  const std::string spec = path.substr(6);
  return volume::field_from_name(spec.substr(0, spec.find(':')));
}

bool samples_field(const ParsedArgs& a) {
  const frame::VolumeMode* mode = a.has("mode") ? frame::find_volume_mode(a.values.at("mode")) : nullptr;
  return mode && mode->samples_field;
}

LoadRequest load_request_from(const ParsedArgs& a, const std::string& path, bool scalar_field) {
  LoadRequest r;
  r.path = path;
  if (a.has("array")) r.array = a.values.at("array");
  if (a.has("component")) {
    const std::string& c = a.values.at("component");
    if (!a.has("array")) throw InputError("--component", "picks a component of the --array NAME");
    r.component = c == "x" || c == "X" ? 0 : c == "y" || c == "Y" ? 1 : c == "z" || c == "Z" ? 2
                  : c == "magnitude" ? -1 : int(parse_uint("component", c));
  }
  if (scalar_field) r.role = io::ArrayRole::Scalars;
  if (a.has("density-scale")) {
    r.density_scale = parse_double("density-scale", a.values.at("density-scale"));
    if (r.density_scale < 0.0) throw InputError("--density-scale", "must not be negative");
  }
  const bool is_vdb = !path.empty() && io::is_vdb_path(path);
  const bool is_image = !path.empty() && io::is_image_volume_path(path);
  if (a.has("subsample") && !is_image && !is_vdb)
    throw InputError("--subsample", "applies to image volumes (.vti .mhd .mha .inr) and OpenVDB grids (.vdb) only");
  if (a.has("grid") && !is_vdb) throw InputError("--grid", "applies to OpenVDB files (.vdb) only");
  if (a.has("grid")) r.vdb_grid = a.values.at("grid");
  r.vdb_marched = is_vdb && samples_field(a);
  const bool is_surface = !path.empty() && io::is_surface_path(path);
  for (const char* option : {"tetgen-quality", "tetgen-max-volume", "tetgen-cells", "remesh"})
    if (a.has(option) && !is_surface) throw InputError(std::string("--") + option, kSurfaceKinds);
  if (a.flags.count("fill-holes") && !is_surface) throw InputError("--fill-holes", kSurfaceKinds);
  r.fill_holes = a.flags.count("fill-holes") > 0;
  if (a.has("tetgen-quality")) r.tetgen.radius_edge_ratio = parse_double("tetgen-quality", a.values.at("tetgen-quality"));
  if (a.has("tetgen-max-volume")) r.tetgen.max_volume = parse_double("tetgen-max-volume", a.values.at("tetgen-max-volume"));
  if (a.has("tetgen-cells")) {
    r.tetgen.target_cells = parse_uint("tetgen-cells", a.values.at("tetgen-cells"));
    if (r.tetgen.target_cells == 0) throw InputError("--tetgen-cells", "must be at least 1");
  }
  if (a.has("remesh")) {
    r.remesh_voxel_size = parse_double("remesh", a.values.at("remesh"));
    if (!(r.remesh_voxel_size > 0.0)) throw InputError("--remesh", "is a voxel size: a positive length");
  }
  if (a.has("subsample")) {
    r.subsample = parse_uint("subsample", a.values.at("subsample"));
    if (*r.subsample == 0) throw InputError("--subsample", "must be at least 1");
  }
  const bool is_exodus = !path.empty() && io::is_exodus_path(path);
  const bool is_series = !path.empty() && io::is_time_series_path(path);
  for (const char* option : {"time-step", "time"})
    if (a.has(option) && !is_series && !is_exodus)
      throw InputError(std::string("--") + option, "picks a step of a time series (.pvd, 'name_*.vtu') or an Exodus II file");
  if (a.has("blocks") && !is_exodus && !(!path.empty() && io::is_multiblock_path(path)))
    throw InputError("--blocks", "picks blocks of a multiblock .vtm or an Exodus II file (.exo .e .ex2 .exii .g .gen)");
  if (a.has("blocks")) r.blocks = block_list(a.values.at("blocks"));
  if (a.has("subdivision")) {
    if (path.empty() || !(io::is_tet_mesh_path(path) || is_series))
      throw InputError("--subdivision", "refines the higher-order cells of unstructured meshes (.vtu .vtk .vtm .pvtu, Exodus II, time series)");
    r.subdivision = parse_uint("subdivision", a.values.at("subdivision"));
    if (r.subdivision > io::kMaxSubdivision)
      throw InputError("--subdivision", "is at most " + std::to_string(io::kMaxSubdivision) + " (each level multiplies a higher-order cell's tetrahedra by about 8)");
  }
  if (a.has("time-step")) r.time_step = parse_uint("time-step", a.values.at("time-step"));
  if (a.has("time")) r.time = parse_double("time", a.values.at("time"));
  return r;
}

LoadRequest load_request_from(const ParsedArgs& a, bool scalar_field) {
  if (a.files.size() > 1) throw InputError(a.files[1], "this command takes one dataset; `prismoid view` opens several");
  return load_request_from(a, a.files.empty() ? std::string() : a.files.front(), scalar_field);
}

TetMesh load_dataset(const LoadRequest& r, const io::Progress& progress) {
  if (r.path.empty()) return load_default(r);
  if (const auto field = field_of_request(r)) return load_field(r, *field);
  if (is_ball_spec(r.path)) return load_ball(r);
  if (io::is_time_series_path(r.path)) return load_time_step(r, progress);
  if (io::is_exodus_path(r.path)) return load_exodus(r, progress);
  if (io::is_surface_path(r.path)) return load_surface(r, progress);
  if (io::is_vdb_path(r.path)) return load_vdb(r, progress);
  if (io::is_image_volume_path(r.path)) return load_image(r, progress);
  // A built-in surface scene's name given to a volume mode (`view cornell-box --mode interval`
  // said "cornell-box: file does not exist"); a file of that name still opens.
  if (is_named_surface_scene(r.path) && !std::filesystem::exists(r.path))
    throw InputError(r.path, "is a built-in surface scene: it opens with a surface --mode (forward, htex, texel, msa, "
                             "fastatlas, path-reference), not with a volume mode");
  return load_unstructured(r, progress);
}

std::string load_label(const LoadRequest& request) {
  if (request.path.empty()) return "the default dataset";
  const std::filesystem::path p(request.path);
  return p.has_filename() && p.has_parent_path() && request.path.find(':') == std::string::npos ? p.filename().string() : request.path;
}

}  // namespace prismoid::app
