#include "io/surface_io.hpp"
#include "io/vdb_io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <utility>
#include <vector>
#include <array>
#include <cstdint>
#include <iostream>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>


#include <vtkAlgorithm.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCleanPolyData.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkFillHolesFilter.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkXMLPolyDataReader.h>

#define TETLIBRARY  // Debian's libtet is built as a library: errors throw an int, never exit()
#include <tetgen.h>

#include <glm/common.hpp>

#include "io/declared_sizes.hpp"
#include "io/image_volume_io.hpp"
#include "io/isolated_read.hpp"
#include "io/off_reader.hpp"
#include "io/path_util.hpp"
#include "io/vtk_grid.hpp"
#include "io/vtk_progress.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace {

vtkSmartPointer<vtkPolyData> read_off(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  const detail::OffPolygons off = detail::parse_off(in, path);
  vtkNew<vtkPoints> points;
  for (const auto& p : off.points) points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> polys;
  std::vector<vtkIdType> ids;
  for (const auto& face : off.faces) {
    ids.assign(face.begin(), face.end());
    polys->InsertNextCell(vtkIdType(ids.size()), ids.data());
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  return poly;
}

vtkSmartPointer<vtkPolyData> read_polydata(const std::string& path, const std::string& ext, const Progress& progress) {
  if (ext == ".off") return read_off(path);
  detail::check_declared_sizes(path);
  vtkSmartPointer<vtkAlgorithm> reader;
  if (ext == ".vtp") {
    auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    if (!r->CanReadFile(path.c_str())) throw InputError(path, "is not a VTK XML polydata file");
    r->SetFileName(path.c_str());
    reader = r;
  } else if (ext == ".stl") {
    auto r = vtkSmartPointer<vtkSTLReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (ext == ".obj") {
    auto r = vtkSmartPointer<vtkOBJReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else {
    auto r = vtkSmartPointer<vtkPLYReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  }
  detail::update_with_progress(reader, progress, {0.0, 0.6, "reading"}, path);
  vtkPolyData* poly = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0));
  if (reader->GetErrorCode() != 0 || !poly || !detail::reported_vtk_error().empty()) {
    const std::string vtk = detail::vtk_problem(detail::reported_vtk_error());
    throw InputError(path, "could not be read as " + ext + " (corrupt or truncated?)" + (vtk.empty() ? "" : " (VTK: " + vtk + ")"));
  }
  return poly;
}

SurfaceMesh to_surface(vtkPolyData* poly, const std::string& name, const Progress& progress = {}) {
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputData(poly);
  vtkNew<vtkCleanPolyData> clean;  // merge coincident points
  clean->SetInputConnection(triangles->GetOutputPort());
  clean->PointMergingOn();
  clean->SetTolerance(0.0);
  detail::update_with_progress(triangles, progress, {0.6, 0.7, "splitting polygons into triangles"}, name);
  detail::update_with_progress(clean, progress, {0.7, 1.0, "merging coincident points"}, name);
  vtkPolyData* out = clean->GetOutput();
  SurfaceMesh s;
  s.name = name;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i) {
    double p[3];
    out->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InputError(name, "point " + std::to_string(i) + " has a non-finite coordinate");
    s.points.emplace_back(p[0], p[1], p[2]);
  }
  vtkCellArray* polys = out->GetPolys();
  vtkNew<vtkIdList> ids;
  // Cell data run over vertices, lines, polygons and strips in that order: a polygon's tuple is
  // at its index among the polygons plus the vertices and lines before them.
  const vtkIdType first_poly = out->GetNumberOfVerts() + out->GetNumberOfLines();
  std::vector<vtkIdType> triangle_cells;
  vtkIdType poly_index = 0;
  for (polys->InitTraversal(); polys->GetNextCell(ids); ++poly_index)
    if (ids->GetNumberOfIds() == 3) {
      s.triangles.push_back({uint32_t(ids->GetId(0)), uint32_t(ids->GetId(1)), uint32_t(ids->GetId(2))});
      triangle_cells.push_back(first_poly + poly_index);
    }
  // Numeric arrays (VTK's readers pass them through the triangle and cleaning filters).
  auto read_arrays = [&](vtkDataSetAttributes* data, vtkIdType tuples, const std::vector<vtkIdType>* rows) {
    std::vector<SurfaceArray> arrays;
    for (int i = 0; data && i < data->GetNumberOfArrays(); ++i) {
      vtkDataArray* array = data->GetArray(i);
      if (!array || !array->GetName() || array->GetNumberOfTuples() < tuples) continue;
      SurfaceArray a;
      a.name = array->GetName();
      a.components = uint32_t(array->GetNumberOfComponents());
      const vtkIdType n = rows ? vtkIdType(rows->size()) : tuples;
      a.values.reserve(size_t(n) * a.components);
      for (vtkIdType t = 0; t < n; ++t)
        for (uint32_t c = 0; c < a.components; ++c) a.values.push_back(array->GetComponent(rows ? (*rows)[size_t(t)] : t, int(c)));
      arrays.push_back(std::move(a));
    }
    return arrays;
  };
  s.point_arrays = read_arrays(out->GetPointData(), out->GetNumberOfPoints(), nullptr);
  s.cell_arrays = read_arrays(out->GetCellData(), out->GetNumberOfCells(), &triangle_cells);
  return s;
}

vtkSmartPointer<vtkPolyData> to_polydata(const SurfaceMesh& s) {
  vtkNew<vtkPoints> points;
  for (const auto& p : s.points) points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> polys;
  for (const auto& t : s.triangles) {
    const vtkIdType ids[3] = {t[0], t[1], t[2]};
    polys->InsertNextCell(3, ids);
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(points);
  poly->SetPolys(polys);
  return poly;
}


// What a TetGen run in a child process reports.
struct TetgenResult {
  int error = 0;               // TetGen stopped with this code
  size_t intersecting_faces = 0;
  std::vector<glm::dvec3> points;
  std::vector<std::array<uint32_t, 4>> tets;
};
template <typename S, Carries<TetgenResult> M>
void fields(S& s, M& r) {
  s(r.error);
  s(r.intersecting_faces);
  s(r.points);
  s(r.tets);
}

void fill_tetgen_input(const SurfaceMesh& surface, tetgenio& in) {
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(surface.points.size());
  in.pointlist = new REAL[surface.points.size() * 3];
  for (size_t i = 0; i < surface.points.size(); ++i)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = surface.points[i][k];
  in.numberoffacets = static_cast<int>(surface.triangles.size());
  in.facetlist = new tetgenio::facet[surface.triangles.size()];
  for (size_t f = 0; f < surface.triangles.size(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) facet.polygonlist[0].vertexlist[k] = static_cast<int>(surface.triangles[f][k]);
  }
}

struct TetgenRequest {
  SurfaceMesh surface;
  std::string switches;
};
template <typename S, Carries<TetgenRequest> M>
void fields(S& s, M& r) {
  s(r.surface);
  s(r.switches);
}

const ChildWork<TetgenRequest, TetgenResult> kTetgen("tetgen", [](const TetgenRequest& request, const Progress&) {
  const SurfaceMesh& surface = request.surface;
  const std::string& switches = request.switches;
  TetgenResult r;
  try {
    {
      tetgenio in, out;
      fill_tetgen_input(surface, in);
      std::string detect = "pdQ";
      ::tetrahedralize(detect.data(), &in, &out);
      r.intersecting_faces = size_t(std::max(out.numberoftrifaces, 0));
    }
    if (r.intersecting_faces == 0) {
      tetgenio in, out;
      fill_tetgen_input(surface, in);
      std::string text = switches;
      ::tetrahedralize(text.data(), &in, &out);
      r.points.reserve(size_t(out.numberofpoints));
      for (int i = 0; i < out.numberofpoints; ++i)
        r.points.emplace_back(out.pointlist[3 * i], out.pointlist[3 * i + 1], out.pointlist[3 * i + 2]);
      r.tets.reserve(size_t(out.numberoftetrahedra));
      for (int t = 0; t < out.numberoftetrahedra; ++t) {
        const int* corners = out.tetrahedronlist + size_t(t) * size_t(out.numberofcorners);
        r.tets.push_back({uint32_t(corners[0]), uint32_t(corners[1]), uint32_t(corners[2]), uint32_t(corners[3])});
      }
    }
  } catch (int code) {  // TETLIBRARY: TetGen's errors are thrown ints
    r = TetgenResult{};
    r.error = code == 0 ? -1 : code;
  }
  return r;
});

// TetGen 1.5.0 frees its memory twice when it stops on bad input (a crash in
// tetgenmesh::freememory), and its memory grows with the cells asked for, so it runs in a child
// process (io/isolated_read.hpp): a crash there is an InputError here, and Ctrl-C or Cancel kills
// it. First TetGen's self-intersection check (-d), then the tetrahedralization.
TetgenResult run_tetgen_isolated(const SurfaceMesh& surface, const std::string& switches, const Progress& progress) {
  ChildJob job;
  job.source = surface.name;
  job.worker = "TetGen";
  job.crash_hint = "the surface probably intersects itself or has features below its tolerance";
  job.memory_hint = "ask for fewer cells (a larger --tetgen-max-volume or a smaller --tetgen-cells)";
  job.stage = "TetGen";
  job.waiting_fraction = -1.0;  // TetGen cannot tell how far it is
  // No time limit: TetGen's time grows with the cells asked for, which are bounded before it starts.
  job.limits.memory_bytes = child_memory_budget();
  return kTetgen(job, progress, {surface, switches});
}

const ChildWork<std::string, SurfaceMesh> kReadSurface("read-surface", [](const std::string& path, const Progress& reporting) {
  const detail::QuietVtk quiet;  // failures become InputErrors, not console noise
  const vtkSmartPointer<vtkPolyData> poly = read_polydata(path, detail::lower_extension(path), reporting);
  SurfaceMesh s = to_surface(poly, path, reporting);
  if (s.triangles.empty()) throw InputError(path, "has no surface triangles");
  return s;
});

}  // namespace

bool is_surface_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  return ext == ".vtp" || ext == ".stl" || ext == ".obj" || ext == ".ply" || ext == ".off";
}

SurfaceMesh read_surface(const std::string& path, const Progress& progress) {
  detail::require_regular_file(path);
  if (!is_surface_path(path)) throw InputError(path, "is not a surface file (.vtp .stl .obj .ply .off)");
  // The readers run in a child process (io/isolated_read.hpp): VTK's PLY reader, for one,
  // crashes on truncated files.
  return kReadSurface(read_job(path), progress, path);
}

SurfaceCheck check_surface(const SurfaceMesh& surface) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (const auto& t : surface.triangles)
    for (int i = 0; i < 3; ++i) ++uses[std::minmax(t[i], t[(i + 1) % 3])];
  SurfaceCheck c;
  bool found = false;
  for (const auto& [edge, n] : uses) {
    if (n == 2) continue;
    (n == 1 ? c.boundary_edges : c.nonmanifold_edges)++;
    if (!found) c.first_problem = 0.5 * (surface.points[edge.first] + surface.points[edge.second]);
    found = true;
  }
  return c;
}

SurfaceMesh fill_holes(const SurfaceMesh& surface) {
  vtkNew<vtkFillHolesFilter> fill;
  fill->SetInputData(to_polydata(surface));
  fill->SetHoleSize(1e300);  // every hole, whatever its size
  fill->Update();
  return to_surface(fill->GetOutput(), surface.name);
}

double enclosed_volume(const SurfaceMesh& surface) {
  // Sum of the signed volumes of the tetrahedra joining each triangle to a point; the bounds'
  // centre keeps the terms small (less cancellation) for surfaces far from the origin.
  glm::dvec3 lo(0.0), hi(0.0);
  if (!surface.points.empty()) lo = hi = surface.points.front();
  for (const auto& p : surface.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 o = 0.5 * (lo + hi);
  double volume = 0.0;
  for (const auto& t : surface.triangles)
    volume += signed_volume(o, surface.points[t[0]], surface.points[t[1]], surface.points[t[2]]);
  return volume;
}

namespace {

TetMesh run_tetgen(const SurfaceMesh& surface, double radius_edge_ratio, double max_volume, const Progress& progress) {
  // p: a piecewise linear complex; q: quality; a: volume bound; Q: quiet.
  std::ostringstream switches;
  switches << "pq" << radius_edge_ratio;
  if (max_volume > 0.0) switches << "a" << max_volume;
  switches << "Q";
  const std::string text = switches.str();
  const TetgenResult result = run_tetgen_isolated(surface, text, progress);
  if (result.error != 0) {
    const int code = result.error;
    const char* why = code == 3   ? "the surface intersects itself"
                      : code == 4 ? "it has a feature smaller than TetGen's tolerance"
                      : code == 5 ? "two of its facets are too close"
                      : code == 1 ? "TetGen ran out of memory"
                                  : "TetGen rejected the input";
    throw InputError(surface.name, std::string("cannot be tetrahedralized: ") + why + " (TetGen error " + std::to_string(code) + ")");
  }
  if (result.intersecting_faces > 0)
    throw InputError(surface.name, "cannot be tetrahedralized: the surface intersects itself (" +
                                       std::to_string(result.intersecting_faces) + " facets cross another)");
  TetMesh mesh;
  mesh.name = surface.name + " (TetGen -" + text + ")";
  mesh.points = result.points;
  mesh.tets = result.tets;
  mesh.cell_extinction.assign(mesh.tets.size(), 1.0);
  if (mesh.tets.empty()) throw InputError(surface.name, "TetGen produced no tetrahedra");
  return mesh;
}

double relative_miss(size_t cells, uint64_t target) { return std::abs(double(cells) - double(target)) / double(target); }

}  // namespace

TetMesh tetrahedralize(const SurfaceMesh& surface, const TetgenOptions& options, const Progress& progress) {
  const SurfaceCheck check = check_surface(surface);
  if (!check.closed()) {
    std::ostringstream msg;
    msg << "is not a closed surface: " << check.boundary_edges << " boundary (hole) edges and " << check.nonmanifold_edges
        << " non-manifold edges, the first near (" << check.first_problem.x << ", " << check.first_problem.y << ", "
        << check.first_problem.z << "); TetGen needs a closed surface (--fill-holes closes holes)";
    throw InputError(surface.name, msg.str());
  }
  if (!(options.radius_edge_ratio >= 1.0) || !std::isfinite(options.radius_edge_ratio))
    throw InputError("--tetgen-quality", "the radius-edge bound must be a number of at least 1");
  if (!(options.max_volume >= 0.0) || !std::isfinite(options.max_volume))
    throw InputError("--tetgen-max-volume", "the volume bound must be a finite number, not negative (0: no bound)");
  if (options.target_cells > kInteractiveMaxCells)
    throw InputError("--tetgen-cells", "asks for " + std::to_string(options.target_cells) + " tetrahedra, more than the " +
                                           std::to_string(kInteractiveMaxCells) + " Prismoid fills a surface with");
  // The cell guard, decided before TetGen runs: with a volume bound a, cells fill the enclosed
  // volume V at most a each, so TetGen makes at least V / a of them.
  const double volume = std::abs(enclosed_volume(surface));
  const double fewest_cells = options.max_volume > 0.0 ? volume / options.max_volume : 0.0;
  if (fewest_cells > double(kInteractiveMaxCells)) {
    std::ostringstream msg;
    msg << "asks for at least " << std::llround(std::min(fewest_cells, 1e18)) << " tetrahedra (the enclosed volume " << volume
        << " / the bound " << options.max_volume << "), more than the " << kInteractiveMaxCells
        << " Prismoid fills a surface with; a bound of at least " << volume / double(kInteractiveMaxCells) << " fits";
    throw InputError("--tetgen-max-volume", msg.str());
  }
  if (options.target_cells == 0) return run_tetgen(surface, options.radius_edge_ratio, options.max_volume, progress);
  if (options.max_volume > 0.0) throw InputError("--tetgen-cells", "sets the volume bound itself: give it or --tetgen-max-volume, not both");

  // Cells fill the volume at about `a` each when the bound binds, so a = V / N first. Quality
  // refinement and the surface's own detail add cells beyond that, and the count falls more
  // slowly than 1 / a: model count = k a^-p, correcting first with p = 1, then with p measured
  // from the last two runs (a secant step in log-log), kept within [0.3, 1.5] against noise.
  // Corrections never take the bound below the cell guard's.
  if (!(volume > 0.0)) throw InputError(surface.name, "encloses no volume, so no cell count can be aimed at (--tetgen-cells)");
  const uint64_t target = options.target_cells;
  const double smallest_bound = volume / double(kInteractiveMaxCells);
  double bound = volume / double(target), previous_bound = 0.0;
  size_t previous_count = 0;
  TetMesh last = run_tetgen(surface, options.radius_edge_ratio, bound, progress);
  TetMesh best = last;
  for (int correction = 0; correction < 2 && relative_miss(best.tets.size(), target) > kTargetCellsTolerance; ++correction) {
    const double count = double(last.tets.size());
    double exponent = 1.0;
    if (previous_count > 0 && previous_count != last.tets.size())
      exponent = std::clamp(std::log(double(previous_count) / count) / std::log(bound / previous_bound), 0.3, 1.5);
    previous_bound = bound;
    previous_count = last.tets.size();
    bound = std::max(smallest_bound, bound * std::pow(count / double(target), 1.0 / exponent));
    last = run_tetgen(surface, options.radius_edge_ratio, bound, progress);
    if (relative_miss(last.tets.size(), target) < relative_miss(best.tets.size(), target)) best = last;
  }
  return best;
}

namespace {

// FNV-1a, 64 bits: a content key, not a security measure.
uint64_t fnv1a(const std::string& bytes, uint64_t h = 1469598103934665603ull) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string default_cache_dir() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/prismoid";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/prismoid";
  return "";
}

}  // namespace

SurfaceTets surface_to_tets(const std::string& path, const SurfaceToTets& options) {
  detail::require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot be read");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  std::ostringstream key;
  key << "q" << options.tetgen.radius_edge_ratio << " a" << options.tetgen.max_volume << " n" << options.tetgen.target_cells
      << " fill" << options.fill_holes << " remesh" << options.remesh_voxel_size << " v1";  // bump when the conversion changes
  const uint64_t hash = fnv1a(key.str(), fnv1a(bytes.str()));
  SurfaceTets result;
  const std::string dir = options.cache_dir.empty() ? default_cache_dir() : options.cache_dir;
  if (!dir.empty()) {
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.vtu", static_cast<unsigned long long>(hash));
    result.cache_file = dir + "/" + name;
  }
  std::error_code no_cache;
  if (!result.cache_file.empty() && std::filesystem::is_regular_file(result.cache_file, no_cache)) {
    try {
      result.mesh = read_tet_mesh(result.cache_file);
      result.mesh.name = path;
      result.from_cache = true;
      return result;
    } catch (const InputError&) {
      // A damaged cache entry: make it again.
    }
  }
  SurfaceMesh surface = read_surface(path, options.progress);
  if (options.fill_holes) surface = fill_holes(surface);
  if (options.remesh_voxel_size > 0.0) surface = remesh_through_level_set(surface, options.remesh_voxel_size, options.progress);
  result.triangles = surface.triangles.size();
  result.mesh = tetrahedralize(surface, options.tetgen, options.progress);
  if (!result.cache_file.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    // Written beside the entry and renamed, so a reader never meets half an entry.
    const std::string partial = result.cache_file + ".partial-" + std::to_string(::getpid()) + ".vtu";
    try {
      if (!ec) {
        write_tet_mesh_vtu(partial, result.mesh);
        std::filesystem::rename(partial, result.cache_file, ec);
        if (ec) std::filesystem::remove(partial, ec);
      }
    } catch (const InputError&) {
      // An unwritable cache costs only the next load's time.
    }
  }
  return result;
}

}  // namespace prismoid::io
