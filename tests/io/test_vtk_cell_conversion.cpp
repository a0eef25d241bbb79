// Non-tetrahedral cells become conforming tetrahedra: every interior triangle is shared by
// exactly two tetrahedra, the unshared ones lie on the box's boundary and cover its area,
// and the volume is the box's (computed from its extents, not from the conversion).
#include <gtest/gtest.h>

#include "support/mesh_faces.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>

#include "io/vtk_tet_io.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_quality.hpp"
#include "vtk_test_grids.hpp"

namespace prismoid {
namespace {

using testgrids::Cut;

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("prismoid_conv_" + std::to_string(::getpid()) + "_" + name)).string();
}

struct Faces {
  size_t interior = 0;      // shared by exactly two tetrahedra
  size_t overshared = 0;    // by three or more: overlapping tetrahedra
  size_t off_boundary = 0;  // unshared but not on the box's boundary: a crack
  double boundary_area = 0.0;
};

Faces faces_of(const TetMesh& mesh, const testgrids::Lattice& l) {
  const std::map<std::array<uint32_t, 3>, int> count = test::face_uses(mesh);
  const glm::dvec3 lo(l.xs.front(), l.ys.front(), l.zs.front()), hi(l.xs.back(), l.ys.back(), l.zs.back());
  Faces faces;
  for (const auto& [f, n] : count) {
    if (n == 2) ++faces.interior;
    if (n > 2) ++faces.overshared;
    if (n != 1) continue;
    const glm::dvec3 a = mesh.points[f[0]], b = mesh.points[f[1]], c = mesh.points[f[2]];
    faces.boundary_area += 0.5 * glm::length(glm::cross(b - a, c - a));
    // On a boundary plane means all three corners share the plane's coordinate exactly (the
    // coordinates are copied from the lattice, never computed).
    bool on_plane = false;
    for (int axis = 0; axis < 3; ++axis)
      for (double plane : {lo[axis], hi[axis]}) on_plane = on_plane || (a[axis] == plane && b[axis] == plane && c[axis] == plane);
    if (!on_plane) ++faces.off_boundary;
  }
  return faces;
}

// Sums of a few hundred volumes and areas of size ~0.1 to 10: the relative rounding error is
// below (cells) x eps; 1e-12 relative leaves a wide margin and is far below any missing cell.
constexpr double kRelative = 1e-12;

void expect_conforming_box(const TetMesh& mesh, const testgrids::Lattice& l, const std::string& what) {
  SCOPED_TRACE(what);
  const Faces f = faces_of(mesh, l);
  EXPECT_EQ(f.overshared, 0u);
  EXPECT_EQ(f.off_boundary, 0u);
  EXPECT_GT(f.interior, 0u);
  EXPECT_NEAR(f.boundary_area, l.area(), kRelative * l.area());
  EXPECT_NEAR(tet_quality(mesh).total_volume, l.volume(), kRelative * l.volume());
}

class Conversion : public ::testing::TestWithParam<Cut> {};

TEST_P(Conversion, IsConformingAndKeepsVolumeAreaAndArrays) {
  const testgrids::Lattice lattice = testgrids::make_lattice(3);
  auto grid = testgrids::make_grid(lattice, GetParam());
  const std::string path = temp_path("cells.vtu");
  testgrids::write_vtu(path, grid);
  io::MeshConversion report;
  const TetMesh mesh = io::read_tet_mesh(path, {.array = "cell_id", .role = io::ArrayRole::Scalars}, &report);
  expect_conforming_box(mesh, lattice, "cell_id");
  EXPECT_TRUE(report.split());
  EXPECT_EQ(report.tets_out, mesh.tets.size());
  size_t cells_in = 0;
  for (const auto& [name, count] : report.cells_in) cells_in += count;
  EXPECT_EQ(cells_in, size_t(grid->GetNumberOfCells()));
  EXPECT_EQ(report.zero_volume, 0u);
  // Cells wound as VTK defines them split into positively oriented tetrahedra, so the
  // "inverted" note speaks of the file's own tetrahedra, never of the split.
  EXPECT_EQ(report.inverted, 0u);
  EXPECT_NE(io::conversion_note(report).find("into " + std::to_string(mesh.tets.size()) + " tetrahedra"), std::string::npos);

  // Each tetrahedron carries its cell's value and lies inside that cell: its centroid is in
  // the cell's bounding box (cells are convex and their boxes are the cells' extents).
  ASSERT_EQ(mesh.cell_scalars.size(), mesh.tets.size());
  std::vector<size_t> tets_of_cell(size_t(grid->GetNumberOfCells()), 0);
  for (size_t t = 0; t < mesh.tets.size(); ++t) {
    const double value = mesh.cell_scalars[t];
    ASSERT_EQ(value, std::floor(value));
    ASSERT_GE(value, 0.0);
    ASSERT_LT(value, double(grid->GetNumberOfCells()));
    const vtkIdType cell = vtkIdType(value);
    ++tets_of_cell[size_t(cell)];
    double b[6];
    grid->GetCellBounds(cell, b);
    glm::dvec3 centroid(0.0);
    for (uint32_t p : mesh.tets[t]) centroid += 0.25 * mesh.points[p];
    EXPECT_TRUE(centroid.x > b[0] && centroid.x < b[1] && centroid.y > b[2] && centroid.y < b[3] && centroid.z > b[4] && centroid.z < b[5])
        << "tetrahedron " << t << " of cell " << cell;
  }
  for (size_t c = 0; c < tets_of_cell.size(); ++c) EXPECT_GE(tets_of_cell[c], 2u) << "cell " << c;  // a pyramid gives 2

  // Point arrays are kept with the points: scalars exactly, vectors by magnitude.
  const TetMesh heights = io::read_tet_mesh(path, {.array = "height", .role = io::ArrayRole::Scalars});
  ASSERT_EQ(heights.points.size(), size_t(grid->GetNumberOfPoints()));
  for (size_t p = 0; p < heights.points.size(); ++p) EXPECT_EQ(heights.point_scalars[p], heights.points[p].z);
  const TetMesh speeds = io::read_tet_mesh(path, {.array = "velocity", .role = io::ArrayRole::Scalars});
  for (size_t p = 0; p < speeds.points.size(); ++p)
    EXPECT_DOUBLE_EQ(speeds.point_scalars[p], std::sqrt(1.0 + speeds.points[p].z * speeds.points[p].z));
  std::filesystem::remove(path);
}

std::string cut_name(const ::testing::TestParamInfo<Cut>& cut) {
  static const char* const kNames[] = {"Hexahedra", "Voxels", "Wedges", "Pyramids", "Mixed"};
  return kNames[int(cut.param)];
}

INSTANTIATE_TEST_SUITE_P(Cells, Conversion, ::testing::Values(Cut::Hexahedra, Cut::Voxels, Cut::Wedges, Cut::Pyramids, Cut::Mixed),
                         cut_name);

TEST(Conversion, ShuffledIdsAndWarpedFacesStillConform) {
  // Other id orders give other diagonals; the shared faces must agree for every one of them.
  // Interior corners moved by up to 10% make the quads non-planar: two neighbours splitting a
  // shared quad along different diagonals would then overlap or leave a gap, and the volume
  // and face counts would show it.
  const testgrids::Lattice lattice = testgrids::make_lattice(4);
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const std::string path = temp_path("seed.vtu");
    testgrids::write_vtu(path, testgrids::make_grid(lattice, Cut::Mixed, seed, 0.1));
    expect_conforming_box(io::read_tet_mesh(path), lattice, "seed " + std::to_string(seed));
    std::filesystem::remove(path);
  }
}

TEST(Conversion, TheConformityCheckSeesHolesAndOverlaps) {
  // The checker itself must fail on a broken mesh: one tetrahedron removed leaves its four
  // faces unshared, inside the box; one duplicated makes its faces shared three times.
  const testgrids::Lattice lattice = testgrids::make_lattice(3);
  const std::string path = temp_path("control.vtu");
  testgrids::write_vtu(path, testgrids::make_grid(lattice, Cut::Hexahedra));
  const TetMesh mesh = io::read_tet_mesh(path);
  std::filesystem::remove(path);
  ASSERT_EQ(faces_of(mesh, lattice).off_boundary, 0u);
  // The centre cube's tetrahedra touch no boundary: removing one opens four interior faces.
  size_t inner = mesh.tets.size();
  for (size_t t = 0; t < mesh.tets.size() && inner == mesh.tets.size(); ++t) {
    bool touches = false;
    for (uint32_t p : mesh.tets[t])
      for (int axis = 0; axis < 3; ++axis) {
        const double v = mesh.points[p][axis];
        touches = touches || v == lattice.xs.front() || v == lattice.xs.back() || v == lattice.ys.back() || v == lattice.zs.back();
      }
    if (!touches) inner = t;
  }
  ASSERT_LT(inner, mesh.tets.size());
  TetMesh holed = mesh;
  holed.tets.erase(holed.tets.begin() + long(inner));
  EXPECT_EQ(faces_of(holed, lattice).off_boundary, 4u);
  TetMesh doubled = mesh;
  doubled.tets.push_back(mesh.tets[inner]);
  EXPECT_EQ(faces_of(doubled, lattice).overshared, 4u);
}

// Two quadratic hexahedra with straight edges (mid-edge nodes at the edge midpoints) sharing
// a face: split through all 20 nodes each, the result fills the two boxes and conforms.
TEST(Conversion, QuadraticHexahedraSplitThroughAllTheirNodes) {
  testgrids::Lattice l;
  l.xs = {0.0, 1.0, 2.5};
  l.ys = {0.0, 0.75};
  l.zs = {0.0, 1.25};
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  std::map<std::array<int, 3>, vtkIdType> ids;  // lattice position in half steps -> point id
  auto point = [&](int hx, int hy, int hz) {
    auto [it, fresh] = ids.try_emplace({hx, hy, hz}, points->GetNumberOfPoints());
    auto coord = [](const std::vector<double>& axis, int h) { return h % 2 ? 0.5 * (axis[size_t(h / 2)] + axis[size_t(h / 2 + 1)]) : axis[size_t(h / 2)]; };
    if (fresh) points->InsertNextPoint(coord(l.xs, hx), coord(l.ys, hy), coord(l.zs, hz));
    return it->second;
  };
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  for (int i = 0; i < 2; ++i) {
    const int x0 = 2 * i, x1 = 2 * i + 2;
    // Corners as in a linear hexahedron, then mid-edge nodes: bottom ring, top ring, verticals.
    const int corners[8][3] = {{x0, 0, 0}, {x1, 0, 0}, {x1, 2, 0}, {x0, 2, 0}, {x0, 0, 2}, {x1, 0, 2}, {x1, 2, 2}, {x0, 2, 2}};
    const int edges[12][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
    vtkIdType node[20];
    for (int c = 0; c < 8; ++c) node[c] = point(corners[c][0], corners[c][1], corners[c][2]);
    for (int e = 0; e < 12; ++e) {
      const int* a = corners[edges[e][0]];
      const int* b = corners[edges[e][1]];
      node[8 + e] = point((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2);
    }
    grid->InsertNextCell(VTK_QUADRATIC_HEXAHEDRON, 20, node);
  }
  const std::string path = temp_path("quadratic.vtu");
  testgrids::write_vtu(path, grid);
  io::MeshConversion report;
  const TetMesh mesh = io::read_tet_mesh(path, {}, &report);
  EXPECT_EQ(report.cells_in.at("vtkQuadraticHexahedron"), 2u);
  expect_conforming_box(mesh, l, "quadratic");
  // Every node is a corner of some tetrahedron: the split goes through the mid-edge nodes.
  std::vector<bool> used(mesh.points.size(), false);
  for (const auto& t : mesh.tets)
    for (uint32_t p : t) used[p] = true;
  EXPECT_EQ(std::count(used.begin(), used.end(), true), long(mesh.points.size()));
  std::filesystem::remove(path);
}

TEST(Conversion, FlatAndInvertedTetrahedraAreKeptAndCounted) {
  const std::string path = temp_path("quality.vtk");
  // A positive tetrahedron, the same with two corners swapped (inverted), and one whose four
  // corners lie in the plane z = 0 (flat).
  std::ofstream(path) << "# vtk DataFile Version 3.0\nq\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n"
                         "0 0 0 1 0 0 0 1 0 0 0 1 1 1 0\nCELLS 3 15\n4 0 1 2 3\n4 1 0 2 3\n4 0 1 2 4\nCELL_TYPES 3\n10\n10\n10\n";
  io::MeshConversion report;
  const TetMesh mesh = io::read_tet_mesh(path, {}, &report);
  EXPECT_EQ(mesh.tets.size(), 3u);
  EXPECT_FALSE(report.split());
  EXPECT_EQ(report.zero_volume, 1u);
  EXPECT_EQ(report.inverted, 1u);
  const std::string note = io::conversion_note(report);
  EXPECT_NE(note.find("1 zero-volume"), std::string::npos) << note;
  EXPECT_NE(note.find("1 inverted"), std::string::npos) << note;
  std::filesystem::remove(path);
}

TEST(Conversion, SurfaceCellsAreDroppedAndAMeshOfOnlySurfacesIsRefused) {
  const std::string mixed = temp_path("with_faces.vtk");
  std::ofstream(mixed) << "# vtk DataFile Version 3.0\nq\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
                          "0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 2 9\n4 0 1 2 3\n3 0 1 2\nCELL_TYPES 2\n10\n5\n";
  io::MeshConversion report;
  EXPECT_EQ(io::read_tet_mesh(mixed, {}, &report).tets.size(), 1u);
  EXPECT_EQ(report.dropped, 1u);
  const std::string surface = temp_path("surface.vtk");
  std::ofstream(surface) << "# vtk DataFile Version 3.0\nq\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 3 double\n"
                            "0 0 0 1 0 0 0 1 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n";
  try {
    io::read_tet_mesh(surface);
    ADD_FAILURE() << "a mesh of triangles has no volume";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no 3D cells"), std::string::npos) << e.what();
  }
  std::filesystem::remove(mixed);
  std::filesystem::remove(surface);
}

TEST(Conversion, IndicesOutOfRangeAreRefusedBeforeVtkTouchesThem) {
  const std::string path = temp_path("range.vtk");
  std::ofstream(path) << "# vtk DataFile Version 3.0\nq\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n"
                         "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1\nCELLS 1 9\n8 0 1 2 3 4 5 6 99\nCELL_TYPES 1\n12\n";
  try {
    io::read_tet_mesh(path);
    ADD_FAILURE() << "point 99 of 8";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out of range"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// A quadratic tetrahedron (straight edges) carrying f = x^2 at its 10 nodes: its own quadratic
// interpolation is f exactly, so what the tetrahedra Prismoid draws hold (f linear in each) is
// held to f itself. Linear interpolation of x^2 on a tetrahedron errs by the variance of its
// corners' x under the barycentric weights, at most (x extent)^2 / 4 (Popoviciu's inequality),
// attained at the midpoint of the edge of largest x extent: each level's measured error is within
// that bound of its own tetrahedra, reaches half of it at least (the samples include those
// midpoints), and shrinks with every level.
TEST(VtkCellConversion, QuadraticFieldIsWithinTheTessellationErrorAtEachSubdivision) {
  const double corner[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const int edge[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {1, 3}, {2, 3}};  // VTK's mid-edge node order
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> f;
  f->SetName("f");
  const auto add = [&](double x, double y, double z) {
    points->InsertNextPoint(x, y, z);
    f->InsertNextValue(x * x);
  };
  for (const auto& c : corner) add(c[0], c[1], c[2]);
  for (const auto& e : edge)
    add(0.5 * (corner[e[0]][0] + corner[e[1]][0]), 0.5 * (corner[e[0]][1] + corner[e[1]][1]), 0.5 * (corner[e[0]][2] + corner[e[1]][2]));
  vtkNew<vtkUnstructuredGrid> grid;
  grid->SetPoints(points);
  grid->GetPointData()->AddArray(f);
  const vtkIdType ids[10] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  grid->InsertNextCell(VTK_QUADRATIC_TETRA, 10, ids);
  const std::string path = temp_path("quadratic.vtu");
  testgrids::write_vtu(path, grid);

  // Samples: the lattice of step 1/32 over the tetrahedron (every level's edge midpoints on it).
  constexpr int kSteps = 32;
  std::vector<glm::dvec3> samples;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; i + j <= kSteps; ++j)
      for (int k = 0; i + j + k <= kSteps; ++k) samples.emplace_back(double(i) / kSteps, double(j) / kSteps, double(k) / kSteps);
  double last_error = 1.0;
  for (uint32_t level = 0; level <= 3; ++level) {
    SCOPED_TRACE("subdivision " + std::to_string(level));
    io::MeshConversion conversion;
    const TetMesh mesh = io::read_tet_mesh(path, {.array = "f", .role = io::ArrayRole::Scalars, .subdivision = level}, &conversion);
    EXPECT_EQ(conversion.higher_order, 1u);
    EXPECT_EQ(conversion.subdivision, level);
    ASSERT_EQ(mesh.point_scalars.size(), mesh.points.size());
    EXPECT_NEAR(tet_quality(mesh).total_volume, 1.0 / 6.0, 1e-12);  // the cell, whole: no gap, no overlap
    double bound = 0.0;
    for (const auto& t : mesh.tets) {
      double lo = 1.0, hi = 0.0;
      for (int c = 0; c < 4; ++c) lo = std::min(lo, mesh.points[t[c]].x), hi = std::max(hi, mesh.points[t[c]].x);
      bound = std::max(bound, 0.25 * (hi - lo) * (hi - lo));
    }
    double error = 0.0;
    for (const glm::dvec3& p : samples) {
      bool found = false;
      for (const auto& t : mesh.tets) {
        const glm::dvec3 a = mesh.points[t[0]];
        const glm::dmat3 m(mesh.points[t[1]] - a, mesh.points[t[2]] - a, mesh.points[t[3]] - a);
        const glm::dvec3 w = glm::inverse(m) * (p - a);
        const double w0 = 1.0 - w.x - w.y - w.z;
        if (std::min({w0, w.x, w.y, w.z}) < -1e-12) continue;
        const double value = w0 * mesh.point_scalars[t[0]] + w.x * mesh.point_scalars[t[1]] + w.y * mesh.point_scalars[t[2]] +
                             w.z * mesh.point_scalars[t[3]];
        error = std::max(error, std::abs(value - p.x * p.x));
        found = true;
        break;
      }
      ASSERT_TRUE(found) << "no tetrahedron holds (" << p.x << ", " << p.y << ", " << p.z << ")";
    }
    std::cout << "subdivision " << level << ": " << mesh.tets.size() << " tetrahedra, largest field error " << error << " (bound " << bound
              << ")\n";
    EXPECT_LE(error, bound + 1e-12);
    EXPECT_GE(error, 0.5 * bound);
    if (level > 0) {
      EXPECT_LT(error, 0.5 * last_error);
    }
    last_error = error;
  }
  // Higher-order cells beside linear ones: tessellating them alone would crack where they meet.
  const vtkIdType hex[8] = {1, 4, 6, 2, 3, 7, 8, 9};  // any eight points: refused before any filter runs
  grid->InsertNextCell(VTK_HEXAHEDRON, 8, hex);
  testgrids::write_vtu(path, grid);
  EXPECT_THROW(io::read_tet_mesh(path, {.subdivision = 1}), InputError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace prismoid
