#include "io/vtk_tet_io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <vector>

#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkDoubleArray.h>
#include <vtkGenericCell.h>
#include <vtkPoints.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "io/exodus_io.hpp"
#include "io/file_write.hpp"
#include "io/path_util.hpp"
#include "io/vtk_grid.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_quality.hpp"

namespace prismoid::io {

namespace {

std::string array_names(vtkFieldData* data) {
  std::string names;
  for (int i = 0; i < data->GetNumberOfArrays(); ++i) {
    const char* n = data->GetArrayName(i);
    names += std::string(names.empty() ? "" : ", ") + (n ? n : "(unnamed)");
  }
  return names.empty() ? "none" : names;
}

// One value per tuple: the chosen component, or vectors by magnitude (component < 0).
// The array ParaView colours a dataset by when none is named (MeshConversion::chosen_array).
struct ChosenArray {
  vtkDataArray* point = nullptr;
  vtkDataArray* cell = nullptr;
  std::string name, why;
};

ChosenArray choose_scalars(vtkUnstructuredGrid* grid) {
  // Prismoid's own files and datasets/fetch-real.sh's carry the extinction they were drawn with:
  // a density, not a field to colour by.
  auto candidates = [](vtkFieldData* data) {
    std::vector<vtkDataArray*> arrays;
    for (int i = 0; i < data->GetNumberOfArrays(); ++i)
      if (vtkDataArray* a = data->GetArray(i); a && a->GetName() && std::string(a->GetName()) != "extinction") arrays.push_back(a);
    return arrays;
  };
  auto named = [](vtkDataArray* a) { return std::string(a->GetName() ? a->GetName() : ""); };
  ChosenArray c;
  if (vtkDataArray* a = grid->GetPointData()->GetScalars(); a && a->GetName()) {
    c.point = a, c.name = named(a), c.why = "the active point scalars";
  } else if (vtkDataArray* b = grid->GetCellData()->GetScalars(); b && b->GetName() && named(b) != "extinction") {
    c.cell = b, c.name = named(b), c.why = "the active cell scalars";
  } else if (const auto points = candidates(grid->GetPointData()); points.size() == 1) {
    c.point = points[0], c.name = named(points[0]), c.why = "the only point array";
  } else if (const auto cells = candidates(grid->GetCellData()); cells.size() == 1) {
    c.cell = cells[0], c.name = named(cells[0]), c.why = "the only cell array";
  }
  return c;
}

double value_of(vtkDataArray* array, vtkIdType i, int component = -1) {
  const int components = array->GetNumberOfComponents();
  if (components == 1) return array->GetComponent(i, 0);
  if (component >= 0) return array->GetComponent(i, component);
  double sum = 0.0;  // vectors by magnitude
  for (int c = 0; c < components; ++c) sum += array->GetComponent(i, c) * array->GetComponent(i, c);
  return std::sqrt(sum);
}

// Counts the cells by type and refuses point indices out of range before any VTK filter
// dereferences them.
void survey_cells(vtkUnstructuredGrid* grid, const std::string& path, MeshConversion& report) {
  const vtkIdType point_count = grid->GetNumberOfPoints();
  vtkNew<vtkIdList> ids;
  std::map<int, int> dimension_of_type;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const int type = grid->GetCellType(c);
    ++report.cells_in[vtkCellTypes::GetClassNameFromTypeId(type)];
    auto [dim, fresh] = dimension_of_type.try_emplace(type, 0);
    if (fresh) {
      vtkSmartPointer<vtkCell> cell;
      cell.TakeReference(vtkGenericCell::InstantiateCell(type));
      dim->second = cell ? cell->GetCellDimension() : 0;
    }
    if (dim->second < 3) ++report.dropped;
    else if (!vtkCellTypes::IsLinear(static_cast<unsigned char>(type))) ++report.higher_order;
    grid->GetCellPoints(c, ids);
    for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
      if (ids->GetId(k) < 0 || ids->GetId(k) >= point_count)
        throw InputError(path, "cell " + std::to_string(c) + " uses point " + std::to_string(ids->GetId(k)) +
                                   " but there are " + std::to_string(point_count) + " points (index out of range)");
  }
}

}  // namespace

bool MeshConversion::split() const {
  for (const auto& [name, count] : cells_in)
    if (name != "vtkTetra" && count > 0) return true;
  return false;
}

std::string conversion_note(const MeshConversion& c) {
  std::vector<std::string> parts;
  if (c.pieces > 1)
    parts.push_back("merged " + std::to_string(c.pieces) + " pieces (" + std::to_string(c.merged_points) + " shared points)");
  if (c.split()) {
    std::string in;
    for (const auto& [name, count] : c.cells_in) in += std::string(in.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    parts.push_back("split " + in + " into " + std::to_string(c.tets_out) + " tetrahedra" +
                    (c.subdivision > 0 ? " (higher-order cells tessellated by VTK's vtkTessellatorFilter, up to " +
                                             std::to_string(c.subdivision) + " subdivisions)"
                     : c.higher_order > 0 ? " (higher-order cells through their nodes: --subdivision N refines them)"
                                          : ""));
  }
  if (c.dropped > 0) parts.push_back("dropped " + std::to_string(c.dropped) + " cells without volume (2D/1D/vertex)");
  for (const std::string& what : c.ignored) parts.push_back("not drawn: " + what);
  if (c.zero_volume > 0) parts.push_back(std::to_string(c.zero_volume) + " zero-volume tetrahedra (kept; they contribute nothing)");
  if (c.inverted > 0) parts.push_back(std::to_string(c.inverted) + " inverted tetrahedra (negative orientation; rendered as they are)");
  std::string note;
  for (const auto& p : parts) note += (note.empty() ? "" : "; ") + p;
  return note;
}

bool is_tet_mesh_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  return ext == ".vtu" || ext == ".vtk" || ext == ".vtm" || ext == ".pvtu" || is_exodus_path(path);
}

bool is_multiblock_path(const std::string& path) { return detail::lower_extension(path) == ".vtm"; }

namespace {

struct ReadResult {
  TetMesh mesh;
  MeshConversion conversion;
};
template <typename S, Carries<ReadResult> M>
void fields(S& s, M& r) {
  s(r.mesh);
  s(r.conversion);
}

// What the reader child needs: the path and the options (their progress is the child's own).
struct ReadRequest {
  std::string path;
  TetReadOptions options;
};
template <typename S, Carries<ReadRequest> M>
void fields(S& s, M& r) {
  s(r.path);
  s(r.options.array);
  s(r.options.component);
  s(r.options.role);
  s(r.options.density_scale);
  s(r.options.blocks);
  s(r.options.time_step);
  s(r.options.subdivision);
}

const ChildWork<ReadRequest, ReadResult> kReadTetMesh("read-tet-mesh", [](const ReadRequest& request, const Progress& progress) {
  const detail::QuietVtk quiet;  // failures become InputErrors, not console noise
  TetReadOptions reading = request.options;
  reading.progress = progress;
  ReadResult r;
  r.mesh = detail::tet_mesh_from_grid(detail::read_unstructured_grid(request.path, progress, 0.7, {request.options.blocks, request.options.time_step}), request.path, reading, &r.conversion);
  return r;
});

}  // namespace

TetMesh read_tet_mesh(const std::string& path, const TetReadOptions& options, MeshConversion* conversion) {
  detail::require_regular_file(path);
  if (!is_tet_mesh_path(path))
    throw InputError(path, "unknown dataset type '" + detail::lower_extension(path) + "' (Prismoid reads meshes .vtu .vtk .vtm .pvtu, Exodus II .exo .e .ex2, time series .pvd, images .vti .mhd .mha .inr, surfaces .vtp .stl .obj .ply .off)");
  // VTK's readers run in a child process (io/isolated_read.hpp): a file that crashes them or
  // makes them allocate without end is an InputError here.
  ReadResult result = kReadTetMesh(read_job(path), options.progress, {path, options});
  if (conversion) *conversion = result.conversion;
  return std::move(result.mesh);
}

namespace detail {

TetMesh tet_mesh_from_grid(const GridSource& source, const std::string& path, const TetReadOptions& options,
                           MeshConversion* conversion) {
  MeshConversion report;
  report.pieces = source.pieces;
  report.merged_points = source.merged_points;
  report.ignored = source.ignored;
  vtkSmartPointer<vtkUnstructuredGrid> grid = source.grid;
  if (grid->GetNumberOfCells() == 0) throw InputError(path, "has no cells (empty mesh)");
  for (vtkIdType i = 0; i < grid->GetNumberOfPoints(); ++i) {  // before any filter computes with them
    double p[3];
    grid->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InputError(path, "point " + std::to_string(i) + " has a non-finite coordinate (NaN or Inf)");
  }
  survey_cells(grid, path, report);
  if (options.subdivision > 0 && report.higher_order > 0) {
    // Tessellating only some cells would leave T-junctions (cracks) where they meet linear ones.
    size_t solid = 0;
    for (const auto& [name, count] : report.cells_in) solid += count;
    if (solid - report.dropped != report.higher_order)
      throw InputError("--subdivision", path + " mixes higher-order and linear 3D cells: tessellating the former alone would leave "
                                              "cracks where they meet (leave --subdivision out: every cell is then split through its nodes)");
    grid = detail::tessellate(grid, path, options.subdivision, options.progress, 0.7, 0.9);
    report.subdivision = options.subdivision;
  }
  if (report.split() || report.dropped > 0) grid = tetrahedralize(grid, path, options.progress, 0.9, 0.95);

  TetMesh mesh;
  mesh.name = path;
  const vtkIdType point_count = grid->GetNumberOfPoints();
  const vtkIdType cell_count = grid->GetNumberOfCells();
  if (cell_count == 0) throw InputError(path, "has no 3D cells (" + conversion_note(report) + ")");
  mesh.points.resize(size_t(point_count));
  for (vtkIdType i = 0; i < point_count; ++i) {
    double p[3];
    grid->GetPoint(i, p);
    mesh.points[size_t(i)] = {p[0], p[1], p[2]};
  }

  vtkDataArray* array = nullptr;        // a cell array: sigma constant per cell
  vtkDataArray* point_array = nullptr;  // a point array: sigma linear in each cell
  if (options.array.empty() && options.role == ArrayRole::Scalars) {
    const ChosenArray chosen = choose_scalars(grid);
    array = chosen.cell;
    point_array = chosen.point;
    report.chosen_array = chosen.name;
    report.chosen_why = chosen.why;
  }
  if (!options.array.empty()) {
    array = grid->GetCellData()->GetArray(options.array.c_str());
    if (!array) point_array = grid->GetPointData()->GetArray(options.array.c_str());
    if (!array && !point_array)
      throw InputError(path, "has no array '" + options.array + "' (cell arrays: " + array_names(grid->GetCellData()) +
                                 "; point arrays: " + array_names(grid->GetPointData()) + ")");
  }
  if (vtkDataArray* chosen = array ? array : point_array; chosen && options.component >= chosen->GetNumberOfComponents()) {
    const int components = chosen->GetNumberOfComponents();
    throw InputError(path, "array '" + options.array + "' has " + std::to_string(components) +
                               (components == 1 ? " component (it is a scalar)" : " components") + "; --component " +
                               std::to_string(options.component) + " does not exist");
  }
  // The raw values are the scalar field; as extinction they are scaled.
  const bool extinction = options.role == ArrayRole::Extinction;
  if (point_array) {
    mesh.point_scalars.resize(mesh.points.size());
    for (vtkIdType i = 0; i < point_count; ++i) mesh.point_scalars[size_t(i)] = value_of(point_array, i, options.component);
    if (extinction) {
      mesh.point_extinction.resize(mesh.points.size());
      for (size_t i = 0; i < mesh.points.size(); ++i) mesh.point_extinction[i] = mesh.point_scalars[i] * options.density_scale;
    }
  }

  vtkNew<vtkIdList> ids;
  mesh.tets.reserve(size_t(cell_count));
  for (vtkIdType c = 0; c < cell_count; ++c) {
    if (grid->GetCellType(c) != VTK_TETRA) continue;  // unreachable after the filter; kept as a guard
    grid->GetCellPoints(c, ids);
    mesh.tets.push_back({uint32_t(ids->GetId(0)), uint32_t(ids->GetId(1)), uint32_t(ids->GetId(2)), uint32_t(ids->GetId(3))});
    double sigma = options.density_scale;
    if (array) {
      mesh.cell_scalars.push_back(value_of(array, c, options.component));
      if (extinction) sigma = mesh.cell_scalars.back() * options.density_scale;
    }
    if (point_array && extinction) {  // the cell's mean, for statistics; rendering interpolates the points
      sigma = 0.0;
      for (int k = 0; k < 4; ++k) sigma += 0.25 * mesh.point_extinction[size_t(ids->GetId(k))];
    }
    mesh.cell_extinction.push_back(sigma);
  }
  validate(mesh);
  io::report(options.progress, 1.0, "converting to tetrahedra", path);
  const TetQuality quality = tet_quality(mesh);
  report.tets_out = mesh.tets.size();
  report.zero_volume = quality.zero_volume;
  report.inverted = quality.inverted;
  if (conversion) *conversion = report;
  return mesh;
}

}  // namespace detail

void write_tet_mesh_vtu(const std::string& path, const TetMesh& mesh) {
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (const auto& p : mesh.points) points->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->Allocate(vtkIdType(mesh.tets.size()));
  for (const auto& t : mesh.tets) {
    const vtkIdType ids[4] = {t[0], t[1], t[2], t[3]};
    grid->InsertNextCell(VTK_TETRA, 4, ids);
  }
  vtkNew<vtkDoubleArray> sigma;
  sigma->SetName("extinction");
  for (double v : mesh.cell_extinction) sigma->InsertNextValue(v);
  grid->GetCellData()->AddArray(sigma);
  if (!mesh.point_scalars.empty()) {
    vtkNew<vtkDoubleArray> scalars;
    scalars->SetName("scalars");
    for (double v : mesh.point_scalars) scalars->InsertNextValue(v);
    grid->GetPointData()->AddArray(scalars);
  }
  const detail::QuietVtk quiet;  // a failed write is an InputError, not console noise
  // Into memory, then written whole: VTK's own file writing ignores a full disk (the file ends
  // at whatever fitted, and Write() still succeeds).
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->WriteToOutputStringOn();
  writer->SetInputData(grid);
  if (writer->Write() != 1) throw InputError(path, "cannot encode the .vtu file");
  write_file(path, writer->GetOutputString());
}

}  // namespace prismoid::io
