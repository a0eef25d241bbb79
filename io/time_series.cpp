#include "io/time_series.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <sstream>

#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>

#include "io/isolated_read.hpp"
#include "io/path_util.hpp"
#include "io/vtk_grid.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace fs = std::filesystem;

namespace {

std::string number_text(double v) {
  std::ostringstream out;
  out.precision(9);
  out << v;
  return out.str();
}

// A timestep attribute as a number: the whole of it must parse, and be finite.
double parse_time(const std::string& path, size_t index, const char* text) {
  const std::string s = text;
  size_t used = 0;
  double t = 0.0;
  try {
    t = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  while (used < s.size() && std::isspace(static_cast<unsigned char>(s[used]))) ++used;
  if (s.empty() || used != s.size()) throw InputError(path, "data set " + std::to_string(index) + ": timestep '" + s + "' is not a number");
  if (!std::isfinite(t)) throw InputError(path, "data set " + std::to_string(index) + ": timestep '" + s + "' is not a finite number");
  return t;
}

// The collection's data sets, parsed in the reader child: the steps as named, unchecked on disk.
struct ParsedCollection {
  std::vector<TimeStep> steps;
};
template <typename S, Carries<ParsedCollection> M>
void fields(S& s, M& c) {
  s(c.steps);
}

struct CollectionRequest {
  std::string path;
};
template <typename S, Carries<CollectionRequest> M>
void fields(S& s, M& r) {
  s(r.path);
}

const ChildWork<CollectionRequest, ParsedCollection> kReadCollection("read-time-series", [](const CollectionRequest& r, const Progress&) {
  const detail::QuietVtk quiet;
  const std::string& path = r.path;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(path.c_str());
  if (!parser->Parse()) throw InputError(path, "is not a ParaView data collection: its XML does not parse");
  vtkXMLDataElement* root = parser->GetRootElement();
  const char* type = root ? root->GetAttribute("type") : nullptr;
  if (!root || std::string(root->GetName() ? root->GetName() : "") != "VTKFile" || !type || std::string(type) != "Collection")
    throw InputError(path, "is not a ParaView data collection (<VTKFile type=\"Collection\">)");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  if (!collection) throw InputError(path, "has no <Collection> element");
  ParsedCollection c;
  for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = collection->GetNestedElement(i);
    if (!e->GetName() || std::string(e->GetName()) != "DataSet") continue;
    const size_t index = c.steps.size();
    const char* file = e->GetAttribute("file");
    const char* time = e->GetAttribute("timestep");
    if (!file || !*file) throw InputError(path, "data set " + std::to_string(index) + " names no file");
    if (!time) throw InputError(path, "data set " + std::to_string(index) + " (" + file + ") has no timestep: not a time series");
    c.steps.push_back({parse_time(path, index, time), file});
  }
  return c;
});

}  // namespace

bool is_file_series_pattern(const std::string& path) { return fs::path(path).filename().string().find('*') != std::string::npos; }

bool is_time_series_path(const std::string& path) { return detail::lower_extension(path) == ".pvd" || is_file_series_pattern(path); }

namespace {

// A numbered series: the files of the pattern's folder whose names are the pattern with a run of
// digits for its *, in the order of their numbers (as ParaView groups flow_000.vtu ... flow_099.vtu).
TimeSeries read_file_series(const std::string& pattern) {
  const fs::path p(pattern);
  const std::string name = p.filename().string();
  const size_t star = name.find('*');
  if (name.find('*', star + 1) != std::string::npos || p.parent_path().string().find('*') != std::string::npos)
    throw InputError(pattern, "a numbered series has one * in its file name, for the step's number (flow_*.vtu)");
  const std::string prefix = name.substr(0, star), suffix = name.substr(star + 1);
  if (!is_tet_mesh_path(prefix + "0" + suffix)) throw InputError(pattern, "the steps of a numbered series are mesh files (.vtu .vtk .vtm .pvtu)");
  const fs::path folder = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw InputError(pattern, "its folder " + folder.string() + " does not exist");
  struct Numbered {
    std::string digits;  // without leading zeros ("" for 0)
    fs::path file;
  };
  std::vector<Numbered> found;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string f = it->path().filename().string();
    if (f.size() <= prefix.size() + suffix.size() || f.compare(0, prefix.size(), prefix) != 0 ||
        f.compare(f.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string digits = f.substr(prefix.size(), f.size() - prefix.size() - suffix.size());
    if (!std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); })) continue;
    found.push_back({digits.substr(std::min(digits.find_first_not_of('0'), digits.size())), it->path()});
  }
  if (ec) throw InputError(pattern, "its folder cannot be listed: " + ec.message());
  if (found.empty()) throw InputError(pattern, "no file of its folder matches (the * stands for the step's number)");
  // By number: fewer digits first, then digit by digit; one number twice, by name (the listing's
  // order is the file system's).
  std::sort(found.begin(), found.end(), [](const Numbered& a, const Numbered& b) {
    if (a.digits.size() != b.digits.size()) return a.digits.size() < b.digits.size();
    return a.digits != b.digits ? a.digits < b.digits : a.file.filename() < b.file.filename();
  });
  TimeSeries series;
  for (size_t i = 0; i < found.size(); ++i) {
    if (i > 0 && found[i].digits == found[i - 1].digits)
      throw InputError(pattern, found[i - 1].file.filename().string() + " and " + found[i].file.filename().string() + " are both step number " +
                                    (found[i].digits.empty() ? "0" : found[i].digits));
    try {
      detail::require_regular_file(found[i].file.string());
    } catch (const InputError& e) {
      throw InputError(pattern, e.what());
    }
    // A numbered series carries no times: ParaView's file series reader gives each its index.
    series.steps.push_back({double(i), (p.parent_path() / found[i].file.filename()).string()});  // as the pattern names its folder
  }
  return series;
}

}  // namespace

TimeSeries read_time_series(const std::string& path) {
  if (is_file_series_pattern(path)) return read_file_series(path);
  detail::require_regular_file(path);
  if (!is_time_series_path(path)) throw InputError(path, "is not a time series (.pvd)");
  const ParsedCollection parsed = kReadCollection(read_job(path), {}, {path});
  if (parsed.steps.empty()) throw InputError(path, "holds no data set: no time step to draw");
  std::error_code ec;
  const fs::path folder = fs::weakly_canonical(fs::absolute(fs::path(path)).parent_path(), ec);
  TimeSeries series;
  for (size_t i = 0; i < parsed.steps.size(); ++i) {
    const TimeStep& step = parsed.steps[i];
    const std::string at = "step " + std::to_string(i) + " (t = " + number_text(step.time) + ", " + step.file + ")";
    if (i > 0 && !(step.time > parsed.steps[i - 1].time))
      throw InputError(path, at + ": times must increase (the step before is at t = " + number_text(parsed.steps[i - 1].time) +
                                 (step.time == parsed.steps[i - 1].time ? "; several parts at one time are not read" : "") + ")");
    const fs::path named(step.file);
    const fs::path file = named.is_absolute() ? named : fs::path(path).parent_path() / named;
    const fs::path resolved = fs::weakly_canonical(fs::absolute(file), ec);
    const auto [end, _] = std::mismatch(folder.begin(), folder.end(), resolved.begin(), resolved.end());
    if (ec || end != folder.end()) throw InputError(path, at + ": lies outside the collection's folder " + folder.string());
    if (is_time_series_path(file.string())) throw InputError(path, at + ": is a collection itself; a time step is one mesh file");
    if (!is_tet_mesh_path(file.string()))
      throw InputError(path, at + ": is not a mesh file a time step can be (.vtu .vtk .vtm .pvtu)");
    try {
      detail::require_regular_file(file.string());
    } catch (const InputError& e) {  // its problem, said of the step
      const std::string problem = std::string(e.what()).substr(e.source().size() + 2);
      throw InputError(path, at + ": " + problem);
    }
    series.steps.push_back({step.time, file.string()});
  }
  return series;
}

size_t pick_time_step(const TimeSeries& series, const std::string& path, std::optional<uint32_t> step, std::optional<double> time) {
  const size_t n = series.steps.size();
  if (step && time) throw InputError("--time-step", "and --time both pick a step: give one");
  if (step) {
    if (*step >= n) throw InputError("--time-step", path + " has " + std::to_string(n) + " steps (0 to " + std::to_string(n - 1) + "), not " + std::to_string(*step));
    return *step;
  }
  if (time) {
    const double first = series.steps.front().time, last = series.steps.back().time;
    if (!std::isfinite(*time) || *time < first || *time > last)
      throw InputError("--time", number_text(*time) + " lies outside " + path + "'s times [" + number_text(first) + ", " + number_text(last) + "]");
    size_t i = 0;
    while (i + 1 < n && series.steps[i + 1].time <= *time) ++i;
    return i;
  }
  return 0;
}

}  // namespace prismoid::io
