#pragma once
// Loading one dataset, apart from the command line: a plain request (what to open and how) and
// a function that turns it into a TetMesh, reporting progress and honouring cancellation
// through io::Progress. No global state and no terminal, so the viewer can run it on a loader
// thread; `render`, `convert` and `view` build the request from their options
// (load_request_from) and run it on the main thread with a terminal progress bar.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "app/common/cli_args.hpp"
#include "io/progress.hpp"
#include "io/surface_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "renderer/volume/analytic_field.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::app {

struct LoadRequest {
  // A file (.vtu .vtk .vtm .pvtu, a time series .pvd, image volume, surface), a field:NAME[:N], grid:NAME[:N] or
  // ball[:S] spec, or empty: the embedded default dataset.
  std::string path;
  std::string array;                 // empty: none chosen
  std::optional<int> component;      // of a vector array; -1 or none: its magnitude
  io::ArrayRole role = io::ArrayRole::Extinction;
  double density_scale = 1.0;
  std::optional<uint32_t> subsample;  // image volumes only
  io::TetgenOptions tetgen;           // surfaces only
  bool fill_holes = false;            // surfaces only
  double remesh_voxel_size = 0.0;     // surfaces only: OpenVDB remeshing before TetGen (0: none)
  std::string vdb_grid;               // .vdb only: the grid (empty: the first float grid)
  // .vdb only: drawn as its active regions for the march modes (the grid is then the field
  // they march) rather than as voxel tetrahedra. Reads through a cache that belongs to the main
  // thread: the viewer's loader never sets it.
  bool vdb_marched = false;
  // A time series (.pvd, numbered files) or an Exodus II file only: the step drawn, by index or by
  // time (io::pick_time_step; neither: the first).
  std::optional<uint32_t> time_step;
  std::optional<double> time;
  std::vector<std::string> blocks;  // .vtm and Exodus II only: the blocks drawn (io::TetReadOptions::blocks)
  uint32_t subdivision = 0;         // unstructured meshes: higher-order cells' level (io::TetReadOptions::subdivision)
};

// The request the dataset options describe for `path`; InputError names an option that is
// malformed or does not apply to that kind of input. scalar_field: the array is the transfer
// function's scalar rather than the extinction.
LoadRequest load_request_from(const ParsedArgs& a, const std::string& path, bool scalar_field);
// The same for the one dataset of a.files (the default when none); InputError for several.
LoadRequest load_request_from(const ParsedArgs& a, bool scalar_field);
// Whether --mode names a volume mode that samples the field itself (frame::VolumeMode::
// samples_field): a .vdb then loads as its active regions rather than as voxel cells.
bool samples_field(const ParsedArgs& a);

// Loads the request's dataset: one branch per kind of input. InputError names the file and the
// problem; io::Cancelled when `progress` asked to stop. Notes (cells split, TetGen's counts,
// long load times) go to stderr. The mesh is not validated here.
TetMesh load_dataset(const LoadRequest& request, const io::Progress& progress = {});

// The times of the steps of a time series (.pvd, 'name_*.vtu') or an Exodus II file; empty for any
// other dataset and for an Exodus file without steps. InputError as the series' reading.
std::vector<double> time_values(const std::string& path);
// The step `request` draws of a dataset whose steps have `times` (its --time-step, or the step
// --time picks; the first by default).
uint32_t step_of_request(const LoadRequest& request, const std::vector<double>& times);

// The analytic field of a field:NAME[:N] or grid:NAME[:N] spec; nullopt for anything else.
std::optional<volume::AnalyticField> field_of_path(const std::string& path);
// The same, and a marched .vdb's grid (vdb_marched).
std::optional<volume::AnalyticField> field_of_request(const LoadRequest& request);

// A short label for the request, for progress bars and messages (the file name).
std::string load_label(const LoadRequest& request);

}  // namespace prismoid::app
