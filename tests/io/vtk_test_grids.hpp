#pragma once
// Small VTK unstructured grids of every 3D cell kind, built in tests with VTK's own data
// model (tests may use VTK; the app's public interfaces may not).
#include <array>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <glm/vec3.hpp>

namespace prismoid::testgrids {

// How each column (i, j) of lattice cubes is cut. Cutting whole columns the same way keeps the
// input conforming: wedges' triangles face only wedges' triangles or the box's top and bottom.
enum class Cut { Hexahedra, Voxels, Wedges, Pyramids, Mixed };

// A rectilinear box of n x n x n cubes with uneven spacing (planar faces, so the volume is exact:
// the product of the extents). Point ids are shuffled so that neighbouring cells see their
// shared faces' corners in different id orders. Cell array "cell_id" (the cell's index) and
// point array "height" (z) and "velocity" (a vector, magnitude sqrt(1 + z^2)).
struct Lattice {
  std::vector<double> xs, ys, zs;
  glm::dvec3 extent() const { return {xs.back() - xs.front(), ys.back() - ys.front(), zs.back() - zs.front()}; }
  double volume() const { const auto e = extent(); return e.x * e.y * e.z; }
  double area() const { const auto e = extent(); return 2.0 * (e.x * e.y + e.y * e.z + e.z * e.x); }
};

inline Lattice make_lattice(int n, double x0 = 0.0) {
  Lattice l;
  for (auto* axis : {&l.xs, &l.ys, &l.zs}) {
    double v = axis == &l.xs ? x0 : 0.0;
    for (int i = 0; i <= n; ++i) { axis->push_back(v); v += 0.5 + 0.25 * double((i * 7 + int(axis - &l.xs)) % 3); }
  }
  return l;
}

inline Cut cut_of(Cut cut, int i, int j) {
  if (cut != Cut::Mixed) return cut;
  switch ((i + 2 * j) % 3) {
    case 0: return Cut::Hexahedra;
    case 1: return Cut::Wedges;
    default: return Cut::Pyramids;
  }
}

// `jitter` > 0 moves interior corners by up to that fraction of the smallest spacing, so quad
// faces are no longer planar: only a conforming split still tiles the box exactly.
inline vtkSmartPointer<vtkUnstructuredGrid> make_grid(const Lattice& l, Cut cut, unsigned seed = 7, double jitter = 0.0) {
  const int n = int(l.xs.size()) - 1;
  const int corner_count = (n + 1) * (n + 1) * (n + 1);
  const int total = corner_count + n * n * n;  // corners, then cube centres (pyramid apexes)
  std::vector<vtkIdType> id(static_cast<size_t>(total));
  for (int i = 0; i < total; ++i) id[size_t(i)] = i;
  std::shuffle(id.begin(), id.end(), std::mt19937(seed));
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(total);
  auto corner = [&](int i, int j, int k) { return id[size_t((k * (n + 1) + j) * (n + 1) + i)]; };
  auto centre = [&](int i, int j, int k) { return id[size_t(corner_count + (k * n + j) * n + i)]; };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) points->SetPoint(corner(i, j, k), l.xs[size_t(i)], l.ys[size_t(j)], l.zs[size_t(k)]);
  std::mt19937 random(seed + 1000);
  std::uniform_real_distribution<double> offset(-jitter * 0.5, jitter * 0.5);  // the smallest spacing is 0.5
  for (int k = 1; k < n; ++k)
    for (int j = 1; j < n; ++j)
      for (int i = 1; i < n; ++i)
        if (jitter > 0.0)
          points->SetPoint(corner(i, j, k), l.xs[size_t(i)] + offset(random), l.ys[size_t(j)] + offset(random), l.zs[size_t(k)] + offset(random));
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        points->SetPoint(centre(i, j, k), 0.5 * (l.xs[size_t(i)] + l.xs[size_t(i) + 1]), 0.5 * (l.ys[size_t(j)] + l.ys[size_t(j) + 1]),
                         0.5 * (l.zs[size_t(k)] + l.zs[size_t(k) + 1]));
  auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
  grid->SetPoints(points);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        // c[a][b][d]: the cube's corner at offsets (a, b, d) along x, y, z.
        vtkIdType c[2][2][2];
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b)
            for (int d = 0; d < 2; ++d) c[a][b][d] = corner(i + a, j + b, k + d);
        switch (cut_of(cut, i, j)) {
          case Cut::Voxels: {
            const vtkIdType v[8] = {c[0][0][0], c[1][0][0], c[0][1][0], c[1][1][0], c[0][0][1], c[1][0][1], c[0][1][1], c[1][1][1]};
            grid->InsertNextCell(VTK_VOXEL, 8, v);
            break;
          }
          case Cut::Wedges: {  // base (0,1,2) wound so its normal points away from (3,4,5)
            const vtkIdType w0[6] = {c[0][0][0], c[0][1][0], c[1][0][0], c[0][0][1], c[0][1][1], c[1][0][1]};
            const vtkIdType w1[6] = {c[1][0][0], c[0][1][0], c[1][1][0], c[1][0][1], c[0][1][1], c[1][1][1]};
            grid->InsertNextCell(VTK_WEDGE, 6, w0);
            grid->InsertNextCell(VTK_WEDGE, 6, w1);
            break;
          }
          case Cut::Pyramids: {  // each face a base, wound so its normal points to the apex (the centre)
            const vtkIdType apex = centre(i, j, k);
            const std::array<std::array<vtkIdType, 4>, 6> bases = {{
                {c[0][0][0], c[1][0][0], c[1][1][0], c[0][1][0]},  // z = 0, normal +z
                {c[0][0][1], c[0][1][1], c[1][1][1], c[1][0][1]},  // z = 1, normal -z
                {c[0][0][0], c[0][1][0], c[0][1][1], c[0][0][1]},  // x = 0, normal +x
                {c[1][0][0], c[1][0][1], c[1][1][1], c[1][1][0]},  // x = 1, normal -x
                {c[0][0][0], c[0][0][1], c[1][0][1], c[1][0][0]},  // y = 0, normal +y
                {c[0][1][0], c[1][1][0], c[1][1][1], c[0][1][1]},  // y = 1, normal -y
            }};
            for (const auto& b : bases) {
              const vtkIdType p[5] = {b[0], b[1], b[2], b[3], apex};
              grid->InsertNextCell(VTK_PYRAMID, 5, p);
            }
            break;
          }
          default: {
            const vtkIdType h[8] = {c[0][0][0], c[1][0][0], c[1][1][0], c[0][1][0], c[0][0][1], c[1][0][1], c[1][1][1], c[0][1][1]};
            grid->InsertNextCell(VTK_HEXAHEDRON, 8, h);
          }
        }
      }
  vtkNew<vtkDoubleArray> cell_id;
  cell_id->SetName("cell_id");
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) cell_id->InsertNextValue(double(c));
  grid->GetCellData()->AddArray(cell_id);
  vtkNew<vtkDoubleArray> height, velocity;
  height->SetName("height");
  velocity->SetName("velocity");
  velocity->SetNumberOfComponents(3);
  for (vtkIdType p = 0; p < total; ++p) {
    const double z = points->GetPoint(p)[2];
    height->InsertNextValue(z);
    velocity->InsertNextTuple3(1.0, 0.0, z);
  }
  grid->GetPointData()->AddArray(height);
  grid->GetPointData()->AddArray(velocity);
  return grid;
}

inline void write_vtu(const std::string& path, vtkUnstructuredGrid* grid) {
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(grid);
  writer->Write();
}

}  // namespace prismoid::testgrids
