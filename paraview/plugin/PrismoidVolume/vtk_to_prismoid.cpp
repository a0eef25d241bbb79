#include "vtk_to_prismoid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <vtkCamera.h>
#include <vtkCellType.h>
#include <vtkCellTypes.h>
#include <vtkColorTransferFunction.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkPiecewiseFunction.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGridBase.h>
#include <vtkVolumeProperty.h>

namespace prismoid::paraview {

namespace {

double value_of(vtkDataArray* array, vtkIdType i, int component) {
  const int n = array->GetNumberOfComponents();
  if (n == 1) return array->GetComponent(i, 0);
  if (component >= 0) return array->GetComponent(i, component);
  double sum = 0.0;
  for (int c = 0; c < n; ++c) sum += array->GetComponent(i, c) * array->GetComponent(i, c);
  return std::sqrt(sum);
}

std::vector<double> values_of(vtkDataArray* array, vtkIdType count, const char* what, int component) {
  if (array->GetNumberOfTuples() != count)
    throw std::runtime_error(std::string("the array '") + (array->GetName() ? array->GetName() : "") + "' has " +
                             std::to_string(array->GetNumberOfTuples()) + " values for " + std::to_string(count) + " " + what);
  std::vector<double> values(static_cast<size_t>(count));
  for (vtkIdType i = 0; i < count; ++i) {
    values[size_t(i)] = value_of(array, i, component);
    if (!std::isfinite(values[size_t(i)]))
      throw std::runtime_error(std::string("the array '") + (array->GetName() ? array->GetName() : "") + "' has a non-finite value");
  }
  return values;
}

constexpr int kSamples = 256;  // samples of a non-linear function between its ends

// Where to sample a VTK transfer function so that the piecewise-linear function through the
// samples is it: at its nodes when every segment is linear (midpoint 0.5 and sharpness 0, at
// `shape` and `shape` + 1 of each node, and `linear_space`), else kSamples + 1 points over `range`.
std::vector<double> sample_at(const std::vector<std::array<double, 6>>& nodes, size_t shape, bool linear_space, const double* range) {
  bool linear = linear_space;
  for (const auto& node : nodes) linear = linear && node[shape] == 0.5 && node[shape + 1] == 0.0;
  std::vector<double> at;
  if (linear)
    for (const auto& node : nodes) at.push_back(node[0]);
  else
    for (int k = 0; k <= kSamples; ++k) at.push_back(range[0] + (range[1] - range[0]) * k / kSamples);
  return at;
}

}  // namespace

TetMesh tet_mesh_from(vtkUnstructuredGridBase* grid, vtkDataArray* scalars, bool per_cell, int component, std::size_t& skipped) {
  if (!scalars) throw std::runtime_error("no array to colour by: choose a point or cell array in Coloring");
  if (component >= scalars->GetNumberOfComponents())
    throw std::runtime_error(std::string("the array '") + (scalars->GetName() ? scalars->GetName() : "") + "' has " +
                             std::to_string(scalars->GetNumberOfComponents()) + " components; colouring asks for component " +
                             std::to_string(component));
  TetMesh mesh;
  mesh.name = "ParaView input";
  const vtkIdType n_points = grid->GetNumberOfPoints();
  mesh.points.resize(static_cast<size_t>(n_points));
  for (vtkIdType i = 0; i < n_points; ++i) {
    double p[3];
    grid->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) throw std::runtime_error("point " + std::to_string(i) + " is not finite");
    mesh.points[size_t(i)] = {p[0], p[1], p[2]};
  }
  std::vector<vtkIdType> kept;  // the input cell of each tetrahedron
  vtkNew<vtkIdList> ids;
  skipped = 0;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) {
    const int type = grid->GetCellType(c);
    if (type != VTK_TETRA) {
      const int dimension = vtkCellTypes::GetDimension(static_cast<unsigned char>(type));
      if (dimension == 3)
        throw std::runtime_error("cell " + std::to_string(c) + " is a 3D cell other than a tetrahedron (VTK type " + std::to_string(type) +
                                 "): tetrahedralize the input first (Filters > Tetrahedralize)");
      ++skipped;
      continue;
    }
    grid->GetCellPoints(c, ids);
    std::array<uint32_t, 4> tet{};
    for (int k = 0; k < 4; ++k) tet[size_t(k)] = static_cast<uint32_t>(ids->GetId(k));
    mesh.tets.push_back(tet);
    kept.push_back(c);
  }
  if (mesh.tets.empty()) throw std::runtime_error("the input has no tetrahedra");
  if (per_cell) {
    const std::vector<double> all = values_of(scalars, grid->GetNumberOfCells(), "cells", component);
    mesh.cell_scalars.reserve(kept.size());
    for (vtkIdType c : kept) mesh.cell_scalars.push_back(all[size_t(c)]);
  } else {
    mesh.point_scalars = values_of(scalars, n_points, "points", component);
  }
  mesh.cell_extinction.assign(mesh.tets.size(), 0.0);  // colour draws extinction from the transfer function
  return mesh;
}

int mapped_component(vtkVolumeProperty* property) {
  vtkColorTransferFunction* color = property ? property->GetRGBTransferFunction(0) : nullptr;
  if (!color || color->GetVectorMode() != vtkScalarsToColors::COMPONENT) return -1;
  return std::max(color->GetVectorComponent(), 0);
}

volume::TransferFunction transfer_function_from(vtkVolumeProperty* property) {
  vtkColorTransferFunction* color = property->GetRGBTransferFunction(0);
  vtkPiecewiseFunction* opacity = property->GetScalarOpacity(0);
  if (!color || color->GetSize() == 0) throw std::runtime_error("the volume has no colour map");
  if (!opacity || opacity->GetSize() == 0) throw std::runtime_error("the volume has no opacity function");
  const double* cr = color->GetRange();
  const double* orange = opacity->GetRange();
  volume::TransferFunction tf;
  tf.name = "ParaView colour map";
  tf.range_lo = std::min(cr[0], orange[0]);
  tf.range_hi = std::max(cr[1], orange[1]);
  if (!(tf.range_hi > tf.range_lo)) tf.range_hi = tf.range_lo + 1.0;  // one value: any range keeps it
  const double span = tf.range_hi - tf.range_lo;
  auto x_of = [&](double s) { return (s - tf.range_lo) / span; };

  // Each node is (scalar, values..., midpoint, sharpness): 6 doubles for colour, 4 for opacity.
  std::vector<std::array<double, 6>> color_nodes(static_cast<size_t>(color->GetSize()));
  for (int i = 0; i < color->GetSize(); ++i) color->GetNodeValue(i, color_nodes[size_t(i)].data());
  std::vector<std::array<double, 6>> opacity_nodes(static_cast<size_t>(opacity->GetSize()));
  for (int i = 0; i < opacity->GetSize(); ++i) opacity->GetNodeValue(i, opacity_nodes[size_t(i)].data());
  for (double s : sample_at(color_nodes, 4, color->GetColorSpace() == VTK_CTF_RGB, cr)) {
    double rgb[3];
    color->GetColor(s, rgb);
    tf.color.push_back({x_of(s), {std::clamp(rgb[0], 0.0, 1.0), std::clamp(rgb[1], 0.0, 1.0), std::clamp(rgb[2], 0.0, 1.0)}});
  }
  for (double s : sample_at(opacity_nodes, 2, true, orange)) tf.opacity.push_back({x_of(s), std::clamp(opacity->GetValue(s), 0.0, 1.0)});

  const double unit = property->GetScalarOpacityUnitDistance(0);
  if (!(unit > 0.0) || !std::isfinite(unit)) throw std::runtime_error("the scalar opacity unit distance must be positive");
  tf.density_scale = 1.0 / unit;
  volume::validate(tf);
  return tf;
}

double largest_opacity(const volume::TransferFunction& tf, double lo, double hi) {
  if (tf.opacity.empty()) return 0.0;
  const auto at = [&](double x) {
    if (x <= tf.opacity.front().x) return tf.opacity.front().opacity;
    if (x >= tf.opacity.back().x) return tf.opacity.back().opacity;
    for (size_t k = 1; k < tf.opacity.size(); ++k)
      if (x <= tf.opacity[k].x) {
        const auto& a = tf.opacity[k - 1];
        const auto& b = tf.opacity[k];
        const double t = b.x > a.x ? (x - a.x) / (b.x - a.x) : 1.0;
        return a.opacity + t * (b.opacity - a.opacity);
      }
    return tf.opacity.back().opacity;
  };
  const double x0 = volume::normalized(tf, lo), x1 = volume::normalized(tf, hi);
  double largest = std::max(at(x0), at(x1));
  for (const auto& point : tf.opacity)
    if (point.x >= x0 && point.x <= x1) largest = std::max(largest, point.opacity);
  return largest;
}

Camera camera_from(vtkCamera* camera) {
  if (camera->GetParallelProjection())
    throw std::runtime_error("parallel projection is not supported yet: turn Camera Parallel Projection off");
  if (camera->GetUseHorizontalViewAngle()) throw std::runtime_error("a horizontal view angle is not supported yet");
  Camera c;
  const double* eye = camera->GetPosition();
  const double* target = camera->GetFocalPoint();
  const double* up = camera->GetViewUp();
  c.eye = {eye[0], eye[1], eye[2]};
  c.target = {target[0], target[1], target[2]};
  c.up = {up[0], up[1], up[2]};
  c.fovy_degrees = camera->GetViewAngle();
  // VTK's near plane as it is: any positive size of data is drawn (an absolute floor hid data
  // smaller than it). A near plane that is not positive falls back to a millionth of the
  // distance to the focal point, a length of the scene's own size.
  const double near_plane = camera->GetClippingRange()[0];
  const double distance = camera->GetDistance();
  c.near_distance = near_plane > 0.0 && std::isfinite(near_plane) ? near_plane : 1e-6 * distance;
  return c;
}

}  // namespace prismoid::paraview
