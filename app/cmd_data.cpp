// `prismoid convert` and `prismoid info`: datasets without rendering.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>

#include <glm/common.hpp>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/dataset_loader.hpp"
#include "app/common/mixed_args.hpp"
#include "app/common/output_files.hpp"
#include "app/common/terminal_progress.hpp"
#include "app/common/volume_option_table.hpp"
#include "app/common/volume_options.hpp"
#include "app/dataset_report.hpp"
#include "io/dataset_info.hpp"
#include "io/image_volume_io.hpp"
#include "io/surface_io.hpp"
#include "io/exodus_io.hpp"
#include "io/time_series.hpp"
#include "io/vdb_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

const char* const kConvertHelp =
    "usage: prismoid convert [IN] OUT.vtu [--array NAME --density-scale S]\n"
    "                        [--tetgen-quality Q --tetgen-max-volume V --tetgen-cells N --fill-holes --remesh H]\n"
    "                        [--blocks LIST] [--time-step N | --time T] [--subdivision N]\n"
    "       prismoid convert IN OUT.vdb [--vdb fog|levelset] [--voxel-size H] [--fill-holes]\n"
    "\n"
    "Writes a tetrahedral mesh as VTK XML (.vtu): the cell array 'extinction' and, where the\n"
    "input has one, the point array 'scalars'. IN is a .vtu/.vtk/.vtm/.pvtu file (other cells are\n"
    "split into tetrahedra, pieces merged: see `prismoid info IN`), an Exodus II file or a time series\n"
    "(--blocks, --time-step and --time pick as render's do; --subdivision refines higher-order\n"
    "cells as render's does), an image volume (.vti .mhd .mha\n"
    ".inr), a field:NAME[:N] dataset, or a closed surface (.vtp .stl .obj .ply .off) tetrahedralized\n"
    "by TetGen (see `render --help`); without IN, the embedded default dataset is written (its point\n"
    "array 'scalars' holds the field sampled at the points) into a new OUT: an existing file alone\n"
    "is refused, as it is most likely an IN whose OUT was forgotten.\n"
    "\n"
    "OUT.vdb: an OpenVDB grid made by OpenVDB's own tools from a closed surface (IN a surface file, or\n"
    "the boundary of any tetrahedral mesh above): meshToLevelSet's narrow-band level set (3 voxels each\n"
    "side; grid 'surface'), or with --vdb fog (the default) that level set through sdfToFogVolume\n"
    "(density 1 inside, 0 outside; grid 'density'). --voxel-size H: default the bounding box's\n"
    "diagonal / 128, at most half the box's thinnest side (coarser grids cannot hold the inside).\n"
    "\n"
    "OUT may not be IN (nor a link to it): converting loses what OUT's format does not keep. It is\n"
    "written beside OUT and renamed, so a failure or Ctrl-C leaves nothing.\n";

namespace {

// IN as a closed surface: read as it is, or the boundary of the tetrahedral mesh it loads as.
int convert_to_vdb(ParsedArgs& a, const std::string& out, OutputFiles& files) {
  if (a.files.size() != 1) throw InputError("convert", "writing .vdb needs IN: a closed surface or a tetrahedral mesh");
  for (const char* option : {"array", "density-scale"})
    if (a.has(option)) throw InputError(std::string("--") + option, "does not apply to .vdb output (a grid made from a surface)");
  io::VdbWriteOptions options;
  const std::string kind = a.has("vdb") ? a.values.at("vdb") : "fog";
  if (kind != "fog" && kind != "levelset") throw InputError("--vdb", "is fog or levelset, not '" + kind + "'");
  options.fog = kind == "fog";
  if (a.has("voxel-size")) {
    options.voxel_size = parse_double("voxel-size", a.values.at("voxel-size"));
    if (!(options.voxel_size > 0.0)) throw InputError("--voxel-size", "must be positive");
  }
  const std::string& in = a.files.front();
  const auto start = std::chrono::steady_clock::now();
  SurfaceMesh surface;
  if (io::is_surface_path(in)) {
    surface = io::read_surface(in);
    if (a.flags.count("fill-holes")) surface = io::fill_holes(surface);
  } else {
    surface = io::boundary_surface(load_scene(a));
    surface.name = in;
  }
  TerminalProgress progress(in);
  options.progress = progress.callback();
  io::VdbWriteReport report;
  files.write(out, [&](const std::string& file) { report = io::write_vdb_from_surface(file, surface, options); });
  progress.throw_if_cancelled(in);  // Ctrl-C after OpenVDB's last progress report: nothing is written
  files.commit();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "wrote " << out << " (" << (options.fog ? "fog volume 'density'" : "level set 'surface'") << ", voxel size "
            << report.voxel_size << ", " << report.active_voxels << " active voxels, from " << surface.triangles.size()
            << " triangles) in " << seconds << " s\n";
  return kOk;
}

}  // namespace

int cmd_convert(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, {"array", "density-scale", "tetgen-quality", "tetgen-max-volume", "tetgen-cells", "subsample", "grid", "vdb",
                                 "voxel-size", "remesh", "blocks", "time-step", "time", "subdivision"},
                       {"help", "fill-holes"});
  if (a.flags.count("help")) { std::cout << kConvertHelp; return kOk; }
  if (a.files.empty() || a.files.size() > 2) throw InputError("convert", "expects [IN] OUT.vtu (see --help)");
  const std::string out = a.files.back();
  a.files.pop_back();
  // `convert mine.vtu`, OUT forgotten, would replace the user's mesh with the default dataset.
  std::error_code ec;
  if (a.files.empty() && std::filesystem::exists(out, ec))
    throw InputError(out, "exists, and convert with one file writes the embedded default dataset into it: to convert it, "
                          "give IN and OUT (convert " + out + " OUT.vtu)");
  OutputFiles files;
  for (const std::string& in : a.files) files.input(in);
  files.output(out, "convert", {".vtu", ".vdb"});
  if (io::is_vdb_path(out)) return convert_to_vdb(a, out, files);
  for (const char* option : {"vdb", "voxel-size"})
    if (a.has(option)) throw InputError(std::string("--") + option, "applies to .vdb output only");
  TetMesh mesh = load_scene(a);
  if (mesh.point_scalars.empty() && mesh.linear_extinction()) mesh.point_scalars = mesh.point_extinction;
  files.write(out, [&](const std::string& file) { io::write_tet_mesh_vtu(file, mesh); });
  files.commit();
  std::cout << "wrote " << out << " (" << mesh.tets.size() << " tetrahedra, " << mesh.points.size() << " points)\n";
  return kOk;
}

const char* const kInfoHelp =
    "usage: prismoid info FILE\n"
    "       prismoid info [FILE] --plan [--mode M] [--quantity Q] [render's volume options, camera,\n"
    "                   --size, --depth-limit]\n"
    "       prismoid info VOLUME SURFACE... --plan [--surface-mode M] [--shadows on|off] [the same options]\n"
    "\n"
    "Describes a mesh file (.vtu, .vtk, .vtm, .pvtu) without rendering: its cells by type, points,\n"
    "point and cell arrays with their ranges (vectors by magnitude), bounds, and what reading it\n"
    "produces: the tetrahedra that other cells split into, zero-volume and inverted tetrahedra,\n"
    "and the GPU memory of the mesh buffers. An Exodus II file (.exo .e .ex2 .exii .g .gen): its\n"
    "element blocks, variables, time steps and sets, then the above for its blocks with 3D cells at\n"
    "its first step. A time series: its steps and times, then the above for its first. An image volume (.vti .mhd .mha .inr): its voxels, value\n"
    "range, bounds and the tetrahedra it becomes. A surface (.vtp .stl .obj .ply .off): its triangles,\n"
    "bounds, and whether it is closed (where it is not), which TetGen needs. An OpenVDB file (.vdb):\n"
    "each grid's type, class, voxel size, active voxels, index and world boxes, value range, leaf\n"
    "nodes, memory, and for float grids the tetrahedra it becomes.\n"
    "\n"
    "--plan: the passes a first frame with those options runs, CPU and GPU, each with the reason it\n"
    "is there, and the passes it leaves out with why (the line `sort` is the visibility sort); no\n"
    "GPU is needed. A later frame from a still camera also skips the ordering (order reused). The\n"
    "camera, --size and --depth-limit are checked as render checks them.\n";

int cmd_info(const std::vector<std::string>& args) {
  // With --plan: render's volume options, its camera, size and depth limit (checked as render
  // checks them; the plan itself depends on none of the last three).
  std::vector<std::string> value_options = with_camera({"size", "depth-limit"});
  value_options.insert(value_options.end(), kVolumeOptions.begin(), kVolumeOptions.end());
  value_options.insert(value_options.end(), kMixedSceneOptions.begin(), kMixedSceneOptions.end());
  std::vector<std::string> flags = {"help", "plan"};
  for (const std::string& f : volume_flag_options()) flags.push_back(f);
  ParsedArgs a = parse(args, 1, value_options, flags);
  if (a.flags.count("help")) { std::cout << kInfoHelp; return kOk; }
  if (a.flags.count("plan")) return info_plan(a);
  if (!a.values.empty() || a.flags.size() > 0)
    throw InputError("info", "--" + (a.values.empty() ? a.flags.begin()->first : a.values.begin()->first) + " applies with --plan only");
  if (a.files.size() != 1) throw InputError("info", "expects one FILE (see --help)");
  const std::string& file = a.files.front();
  if (field_of_path(file))  // an unknown field: InputError listing the known ones
    throw InputError(file, "is an analytic field, not a file: info describes files (render and view draw fields)");
  auto print_bounds = [](const Bounds& b) {
    std::cout << "  bounds: [" << b.min.x << ", " << b.max.x << "] x [" << b.min.y << ", " << b.max.y << "] x [" << b.min.z
              << ", " << b.max.z << "]\n";
  };
  if (io::is_time_series_path(file)) {  // the steps and their times, then the first step's mesh
    const io::TimeSeries series = io::read_time_series(file);
    std::cout << file << " (time series, " << series.steps.size() << (series.steps.size() == 1 ? " step" : " steps")
              << "; render --time-step N or --time T draws one)\n";
    for (size_t i = 0; i < series.steps.size(); ++i)
      std::cout << "  step " << i << ": t = " << json_number(series.steps[i].time) << ", " << series.steps[i].file << "\n";
    const std::string& first = series.steps.front().file;
    std::cout << "step 0: " << format_dataset_info(first, io::describe_dataset(first));
    return kOk;
  }
  if (io::is_exodus_path(file)) {  // blocks, variables and steps, then what the default choice draws
    const io::ExodusInfo info = io::read_exodus_info(file);
    std::cout << file << " (Exodus II: " << info.blocks.size() << (info.blocks.size() == 1 ? " element block, " : " element blocks, ")
              << info.times.size() << (info.times.size() == 1 ? " time step" : " time steps")
              << "; render --blocks LIST picks blocks, --time-step N or --time T a step)\n";
    for (const io::ExodusBlock& b : info.blocks)
      std::cout << "  block " << io::block_label(b) << ": " << b.cells << " " << (b.cell_type.empty() ? "cells" : b.cell_type)
                << (b.solid ? "" : " (no 3D cells: not drawn)") << "\n";
    auto names = [](const std::vector<std::string>& list) {
      std::string text;
      for (const std::string& n : list) text.append(text.empty() ? "" : ", ").append(n);
      return text.empty() ? std::string("none") : text;
    };
    std::cout << "  nodal variables (point arrays): " << names(info.nodal_variables) << "\n  element variables (cell arrays): "
              << names(info.element_variables) << "\n";
    if (info.node_sets + info.side_sets > 0)
      std::cout << "  node sets: " << info.node_sets << ", side sets: " << info.side_sets << " (not drawn)\n";
    for (size_t i = 0; i < info.times.size(); ++i) std::cout << "  step " << i << ": t = " << json_number(info.times[i]) << "\n";
    std::cout << (info.times.empty() ? "" : "step 0, ") << "the blocks with 3D cells: " << format_dataset_info(file, io::describe_dataset(file));
    return kOk;
  }
  if (io::is_image_volume_path(file)) {
    io::ImageReadOptions options;
    options.role = io::ArrayRole::Scalars;
    options.max_cells = io::kInteractiveMaxCells;
    const TetMesh mesh = io::read_image_volume(file, options);
    const auto [lo, hi] = std::minmax_element(mesh.point_scalars.begin(), mesh.point_scalars.end());
    std::cout << file << " (image volume)\n  voxels: " << mesh.points.size() << ", values in [" << *lo << ", " << *hi << "]\n";
    print_bounds(bounds_of(mesh));
    std::cout << "  as tetrahedra: " << mesh.tets.size() << " (6 per cell between 8 voxel centres), " << mesh.points.size()
              << " points\n  GPU memory (mesh buffers): " << double(io::estimated_gpu_bytes(mesh.tets.size(), mesh.points.size())) / 1048576.0
              << " MiB\n";
    return kOk;
  }
  if (io::is_vdb_path(file)) {
    std::cout << format_vdb_info(io::inspect_vdb(file));
    return kOk;
  }
  if (io::is_surface_path(file)) {
    const SurfaceMesh surface = io::read_surface(file);
    const io::SurfaceCheck check = io::check_surface(surface);
    Bounds b;
    b.min = b.max = surface.points.front();
    for (const auto& p : surface.points) {
      b.min = glm::min(b.min, p);
      b.max = glm::max(b.max, p);
    }
    std::cout << file << " (surface)\n  triangles: " << surface.triangles.size() << ", points: " << surface.points.size() << "\n";
    print_bounds(b);
    if (check.closed()) {
      std::cout << "  closed: yes; rendering fills it with tetrahedra by TetGen (-pq1.414 unless --tetgen-* say otherwise)\n";
    } else {
      std::cout << "  closed: no: " << check.boundary_edges << " boundary (hole) edges, " << check.nonmanifold_edges
                << " non-manifold edges, the first near (" << check.first_problem.x << ", " << check.first_problem.y << ", "
                << check.first_problem.z << "); --fill-holes closes holes before TetGen\n";
    }
    return kOk;
  }
  std::cout << format_dataset_info(file, io::describe_dataset(file));
  return kOk;
}

}  // namespace prismoid::app
