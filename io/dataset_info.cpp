#include "io/dataset_info.hpp"

#include <vtkCellData.h>
#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>

#include "io/path_util.hpp"
#include "io/vtk_grid.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_quality.hpp"

namespace prismoid::io {

namespace {

void summarize(vtkFieldData* data, bool per_point, std::vector<ArraySummary>& out) {
  for (int i = 0; i < data->GetNumberOfArrays(); ++i) {
    vtkDataArray* array = data->GetArray(i);
    if (!array) continue;  // string and other non-numeric arrays have no range
    ArraySummary s;
    s.name = array->GetName() ? array->GetName() : "(unnamed)";
    s.per_point = per_point;
    s.components = array->GetNumberOfComponents();
    double range[2] = {0.0, 0.0};
    array->GetRange(range, s.components == 1 ? 0 : -1);  // -1: VTK's range of the vector magnitude
    s.min = range[0];
    s.max = range[1];
    out.push_back(s);
  }
}

}  // namespace

// DatasetInfo through the isolated reader's pipe.
template <typename S, Carries<ArraySummary> M>
void fields(S& s, M& a) {
  s(a.name);
  s(a.per_point);
  s(a.components);
  s(a.min);
  s(a.max);
}
template <typename S, Carries<DatasetInfo> M>
void fields(S& s, M& info) {
  s(info.points);
  s(info.cells_by_type);
  s(info.arrays);
  s(info.bounds);
  s(info.conversion);
  s(info.mesh_points);
  s(info.volume);
  s(info.blocks);
}

namespace {

const ChildWork<std::string, DatasetInfo> kDescribe("describe-dataset", [](const std::string& path, const Progress&) {
  const detail::QuietVtk quiet;
  const detail::GridSource source = detail::read_unstructured_grid(path);
  vtkUnstructuredGrid* grid = source.grid;
  DatasetInfo info;
  info.points = size_t(grid->GetNumberOfPoints());
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) ++info.cells_by_type[vtkCellTypes::GetClassNameFromTypeId(grid->GetCellType(c))];
  summarize(grid->GetPointData(), true, info.arrays);
  summarize(grid->GetCellData(), false, info.arrays);
  const TetMesh mesh = detail::tet_mesh_from_grid(source, path, {}, &info.conversion);
  info.bounds = bounds_of(mesh);
  info.mesh_points = mesh.points.size();
  info.volume = tet_quality(mesh).total_volume;
  info.blocks = source.blocks;
  return info;
});

}  // namespace

DatasetInfo describe_dataset(const std::string& path) {
  detail::require_regular_file(path);
  if (!is_tet_mesh_path(path))
    throw InputError(path, "unknown dataset type '" + detail::lower_extension(path) + "' (info describes .vtu .vtk .vtm .pvtu meshes; render and convert also read images .vti .mhd .mha .inr and surfaces .vtp .stl .obj .ply .off)");
  return kDescribe(read_job(path), {}, path);  // VTK reads in a child (io/isolated_read.hpp)
}

}  // namespace prismoid::io
