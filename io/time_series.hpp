#pragma once
// Time series (issue "Simulations as they come"): a numbered series of mesh files (flow_*.vtu), or
// a ParaView data collection (.pvd) whose data sets are one mesh per time step, as ParaView and
// VTK's writers make them:
//   <VTKFile type="Collection"><Collection>
//     <DataSet timestep="0.5" part="0" file="flow_000.vtu"/> ...
// The collection is read in a reader child (io/isolated_read.hpp) by VTK's XML parser, and every
// step is checked before any is drawn; a step's mesh is then read as any mesh file is.
#include <cstdint>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace prismoid::io {

struct TimeStep {
  double time = 0.0;
  std::string file;  // the step's mesh, as the collection names it, joined to the collection's folder
};
template <typename S, typename M>
  requires std::is_same_v<std::remove_const_t<M>, TimeStep>
void fields(S& s, M& step) {
  s(step.time);
  s(step.file);
}

struct TimeSeries {
  std::vector<TimeStep> steps;  // in time order
};

// Whether `path` names a time series: a .pvd, or a numbered series (a file name with one *, such
// as flow_*.vtu: the files of that folder with a number for the *, in the order of their numbers,
// each at the time of its index, as ParaView's file series reader gives them).
bool is_time_series_path(const std::string& path);
bool is_file_series_pattern(const std::string& path);

// The steps of a numbered series (InputError naming the pattern: more than one *, not mesh files,
// no file matching, two files of one number) or of a .pvd. InputError naming the collection for: XML that does not parse, a root that
// is not a VTKFile of type Collection, no DataSet, a DataSet without a file or a timestep, a
// timestep that is not a finite number, times that do not increase, several parts at one time,
// and a step's file that is missing, not a regular file, another collection (.pvd), not a mesh
// file, or outside the collection's folder.
TimeSeries read_time_series(const std::string& path);

// The step `--time-step N` or `--time T` picks (neither: the first): N must be a step of the
// series; T must lie within its times, and picks the last step at or before T (as ParaView's
// readers snap a time to a step). InputError naming the option otherwise.
size_t pick_time_step(const TimeSeries& series, const std::string& path, std::optional<uint32_t> step, std::optional<double> time);

}  // namespace prismoid::io
