#include "io/vtk_tet_io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkDoubleArray.h>
#include <vtkPoints.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include "io/path_util.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace {


vtkSmartPointer<vtkUnstructuredGrid> read_grid(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  if (ext == ".vtu") {
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    if (!reader->CanReadFile(path.c_str())) throw InputError(path, "is not a VTK XML unstructured grid (.vtu) file");
    reader->SetFileName(path.c_str());
    reader->Update();
    if (reader->GetErrorCode() != 0 || !reader->GetOutput()) throw InputError(path, "VTK could not read the unstructured grid (corrupt file?)");
    return reader->GetOutput();
  }
  vtkNew<vtkUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  if (!reader->OpenVTKFile() || !reader->ReadHeader()) throw InputError(path, "is not a legacy VTK file");
  reader->CloseVTKFile();
  if (!reader->IsFileUnstructuredGrid()) throw InputError(path, "is a legacy VTK file but not an UNSTRUCTURED_GRID");
  reader->Update();
  if (reader->GetErrorCode() != 0 || !reader->GetOutput()) throw InputError(path, "VTK could not read the unstructured grid (corrupt file?)");
  return reader->GetOutput();
}

std::string array_names(vtkFieldData* data) {
  std::string names;
  for (int i = 0; i < data->GetNumberOfArrays(); ++i) {
    const char* n = data->GetArrayName(i);
    names += std::string(names.empty() ? "" : ", ") + (n ? n : "(unnamed)");
  }
  return names.empty() ? "none" : names;
}

double value_of(vtkDataArray* array, vtkIdType i) {
  const int components = array->GetNumberOfComponents();
  if (components == 1) return array->GetComponent(i, 0);
  double sum = 0.0;  // vectors by magnitude
  for (int c = 0; c < components; ++c) sum += array->GetComponent(i, c) * array->GetComponent(i, c);
  return std::sqrt(sum);
}

}  // namespace

bool is_tet_mesh_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  return ext == ".vtu" || ext == ".vtk";
}

TetMesh read_tet_mesh(const std::string& path, const TetReadOptions& options) {
  if (!std::filesystem::exists(path)) throw InputError(path, "file does not exist");
  if (!is_tet_mesh_path(path)) throw InputError(path, "unknown dataset type '" + detail::lower_extension(path) + "' (this build reads .vtu and .vtk)");
  vtkObject::GlobalWarningDisplayOff();  // failures become InputErrors, not console noise
  vtkSmartPointer<vtkUnstructuredGrid> grid = read_grid(path);

  TetMesh mesh;
  mesh.name = path;
  const vtkIdType point_count = grid->GetNumberOfPoints();
  const vtkIdType cell_count = grid->GetNumberOfCells();
  if (cell_count == 0) throw InputError(path, "has no cells");
  mesh.points.resize(size_t(point_count));
  for (vtkIdType i = 0; i < point_count; ++i) {
    double p[3];
    grid->GetPoint(i, p);
    mesh.points[size_t(i)] = {p[0], p[1], p[2]};
  }

  vtkDataArray* array = nullptr;        // a cell array: sigma constant per cell
  vtkDataArray* point_array = nullptr;  // a point array: sigma linear in each cell
  if (!options.array.empty()) {
    array = grid->GetCellData()->GetArray(options.array.c_str());
    if (!array) point_array = grid->GetPointData()->GetArray(options.array.c_str());
    if (!array && !point_array)
      throw InputError(path, "has no array '" + options.array + "' (cell arrays: " + array_names(grid->GetCellData()) +
                                 "; point arrays: " + array_names(grid->GetPointData()) + ")");
  }
  // The raw values are the scalar field; as extinction they are scaled.
  const bool extinction = options.role == ArrayRole::Extinction;
  if (point_array) {
    mesh.point_scalars.resize(mesh.points.size());
    for (vtkIdType i = 0; i < point_count; ++i) mesh.point_scalars[size_t(i)] = value_of(point_array, i);
    if (extinction) {
      mesh.point_extinction.resize(mesh.points.size());
      for (size_t i = 0; i < mesh.points.size(); ++i) mesh.point_extinction[i] = mesh.point_scalars[i] * options.density_scale;
    }
  }

  std::map<std::string, vtkIdType> other_cells;
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cell_count; ++c) {
    const int type = grid->GetCellType(c);
    if (type != VTK_TETRA) {
      ++other_cells[vtkCellTypes::GetClassNameFromTypeId(type)];
      continue;
    }
    grid->GetCellPoints(c, ids);
    mesh.tets.push_back({uint32_t(ids->GetId(0)), uint32_t(ids->GetId(1)), uint32_t(ids->GetId(2)), uint32_t(ids->GetId(3))});
    double sigma = options.density_scale;
    if (array) {
      mesh.cell_scalars.push_back(value_of(array, c));
      if (extinction) sigma = mesh.cell_scalars.back() * options.density_scale;
    }
    if (point_array && extinction) {  // the cell's mean, for statistics; rendering interpolates the points
      sigma = 0.0;
      for (int k = 0; k < 4; ++k) sigma += 0.25 * mesh.point_extinction[size_t(ids->GetId(k))];
    }
    mesh.cell_extinction.push_back(sigma);
  }
  if (!other_cells.empty()) {
    std::string list;
    for (const auto& [name, count] : other_cells) list += std::string(list.empty() ? "" : ", ") + std::to_string(count) + " " + name;
    throw InputError(path, "has cells that are not tetrahedra (" + list +
                               "); splitting them into tetrahedra arrives with the data layer");
  }
  validate(mesh);
  return mesh;
}

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
  // Written beside the target and renamed, so a failed write never leaves a partial file.
  const std::string tmp = path + ".partial";
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(tmp.c_str());
  writer->SetInputData(grid);
  std::error_code ec;
  if (writer->Write() != 1) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path, "cannot write the .vtu file (does the folder exist, is it writable?)");
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw InputError(path, "cannot write the .vtu file: " + ec.message());
}

}  // namespace prismoid::io
