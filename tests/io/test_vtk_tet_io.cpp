#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "io/vtk_tet_io.hpp"
#include "vtk_test_grids.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "scene/input_error.hpp"

namespace prismoid {
namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("prismoid_vtk_" + std::to_string(::getpid()) + "_" + name)).string();
}

void expect_error(const std::string& path, const io::TetReadOptions& options, const std::string& fragment) {
  try {
    io::read_tet_mesh(path, options);
    FAIL() << "expected an InputError containing '" << fragment << "'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), path);
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(VtkTetIo, VtuRoundTripKeepsPointsCellsAndTheChosenArray) {
  const TetMesh mesh = make_box_mesh(glm::dvec3(1e5), glm::dvec3(1e5 + 2.0), 2, [](const glm::dvec3& p) { return p.x - 1e5 + 0.25; });
  const std::string path = temp_path("box.vtu");
  io::write_tet_mesh_vtu(path, mesh);
  const TetMesh back = io::read_tet_mesh(path, {.array = "extinction", .density_scale = 2.0});
  ASSERT_EQ(back.points.size(), mesh.points.size());
  ASSERT_EQ(back.tets.size(), mesh.tets.size());
  EXPECT_EQ(back.points, mesh.points);  // doubles survive exactly, far from the origin too
  EXPECT_EQ(back.tets, mesh.tets);
  for (size_t i = 0; i < mesh.tets.size(); ++i) EXPECT_DOUBLE_EQ(back.cell_extinction[i], 2.0 * mesh.cell_extinction[i]);
  // Without an array every cell has sigma = density scale.
  const TetMesh plain = io::read_tet_mesh(path);
  for (double s : plain.cell_extinction) EXPECT_EQ(s, 1.0);
  std::filesystem::remove(path);
}

TEST(VtkTetIo, UnknownArrayIsNamedWithTheAlternatives) {
  TetMesh mesh = make_box_mesh(glm::dvec3(0), glm::dvec3(1), 1, [](const glm::dvec3&) { return 1.0; });
  const std::string path = temp_path("arrays.vtu");
  io::write_tet_mesh_vtu(path, mesh);
  expect_error(path, {.array = "density"}, "cell arrays: extinction; point arrays: scalars");
  std::filesystem::remove(path);
}

TEST(VtkTetIo, PointArrayGivesLinearExtinction) {
  TetMesh mesh = make_box_mesh(glm::dvec3(0), glm::dvec3(1), 2, [](const glm::dvec3& p) { return 1.0 + p.x; });
  const std::string path = temp_path("points.vtu");
  io::write_tet_mesh_vtu(path, mesh);
  const TetMesh back = io::read_tet_mesh(path, {.array = "scalars", .density_scale = 3.0});
  ASSERT_TRUE(back.linear_extinction());
  for (size_t i = 0; i < mesh.points.size(); ++i) EXPECT_DOUBLE_EQ(back.point_extinction[i], 3.0 * (1.0 + mesh.points[i].x));
  std::filesystem::remove(path);
}

// Reads `path` for a scalar field with no array named; expects `name` picked for `why` ("" for none).
TetMesh read_expecting_choice(const std::string& path, const std::string& name, const std::string& why) {
  io::MeshConversion conversion;
  TetMesh mesh = io::read_tet_mesh(path, {.role = io::ArrayRole::Scalars}, &conversion);
  EXPECT_EQ(conversion.chosen_array, name) << path;
  EXPECT_EQ(conversion.chosen_why, why) << path;
  return mesh;
}

// With no --array, a scalar field is picked as ParaView picks the array it colours by: the
// active scalars, else the only point array, else the only cell array; Prismoid's own
// "extinction" is a density, not a field, and is never picked.
TEST(VtkTetIo, ScalarsWithNoArrayNamedArePickedAsParaViewPicksThem) {
  // One point array beside "extinction": it is the field.
  const TetMesh mesh = make_box_mesh(glm::dvec3(0), glm::dvec3(1), 2, [](const glm::dvec3& p) { return 1.0 + p.x; });
  const std::string one = temp_path("one_array.vtu");
  io::write_tet_mesh_vtu(one, mesh);
  const TetMesh back = read_expecting_choice(one, "scalars", "the only point array");
  ASSERT_EQ(back.point_scalars.size(), mesh.points.size());
  for (size_t i = 0; i < mesh.points.size(); ++i) EXPECT_DOUBLE_EQ(back.point_scalars[i], 1.0 + mesh.points[i].x);
  // As extinction nothing is picked: sigma stays the density scale, as before.
  io::MeshConversion as_extinction;
  const TetMesh plain = io::read_tet_mesh(one, {}, &as_extinction);
  EXPECT_TRUE(as_extinction.chosen_array.empty());
  EXPECT_TRUE(plain.point_scalars.empty());
  std::filesystem::remove(one);

  // Two point arrays ("height", "velocity") and one cell array ("cell_id"), none active: the
  // only cell array. Then "velocity" made the active point scalars: it, by magnitude.
  vtkSmartPointer<vtkUnstructuredGrid> grid = testgrids::make_grid(testgrids::make_lattice(2), testgrids::Cut::Hexahedra);
  const std::string several = temp_path("several.vtu");
  testgrids::write_vtu(several, grid);
  const TetMesh by_cell = read_expecting_choice(several, "cell_id", "the only cell array");
  EXPECT_EQ(by_cell.cell_scalars.size(), by_cell.tets.size());
  grid->GetPointData()->SetActiveScalars("velocity");
  testgrids::write_vtu(several, grid);
  const TetMesh by_active = read_expecting_choice(several, "velocity", "the active point scalars");
  ASSERT_FALSE(by_active.point_scalars.empty());
  for (double v : by_active.point_scalars) EXPECT_GE(v, 1.0);  // |velocity| = sqrt(1 + z^2)
  // Two point arrays and two cell arrays, none active: no field is guessed.
  grid->GetPointData()->SetActiveScalars(nullptr);
  vtkNew<vtkDoubleArray> second;
  second->SetName("pressure");
  second->SetNumberOfValues(grid->GetNumberOfCells());
  second->Fill(2.0);
  grid->GetCellData()->AddArray(second);
  testgrids::write_vtu(several, grid);
  const TetMesh unguessed = read_expecting_choice(several, "", "");
  EXPECT_TRUE(unguessed.point_scalars.empty() && unguessed.cell_scalars.empty());
  std::filesystem::remove(several);
}

TEST(VtkTetIo, LegacyFileWithAHexahedronIsSplitIntoTetrahedra) {
  const std::string path = temp_path("hex.vtk");
  std::ofstream(path) << "# vtk DataFile Version 3.0\nhex\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n"
                         "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1\nCELLS 1 9\n8 0 1 2 3 4 5 6 7\nCELL_TYPES 1\n12\n";
  io::MeshConversion report;
  const TetMesh mesh = io::read_tet_mesh(path, {}, &report);
  EXPECT_EQ(report.cells_in.at("vtkHexahedron"), 1u);
  EXPECT_EQ(report.tets_out, mesh.tets.size());
  EXPECT_GE(mesh.tets.size(), 5u);  // a cube needs at least five tetrahedra
  EXPECT_NE(io::conversion_note(report).find("split 1 vtkHexahedron into"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(VtkTetIo, LegacyTetrahedraWithCellScalarsAreRead) {
  const std::string path = temp_path("tet.vtk");
  std::ofstream(path) << "# vtk DataFile Version 3.0\ntet\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
                         "0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n"
                         "CELL_DATA 1\nSCALARS sigma double 1\nLOOKUP_TABLE default\n2.5\n";
  const TetMesh m = io::read_tet_mesh(path, {.array = "sigma"});
  ASSERT_EQ(m.tets.size(), 1u);
  EXPECT_EQ(m.cell_extinction[0], 2.5);
  EXPECT_EQ(m.points[3], glm::dvec3(0, 0, 1));
  std::filesystem::remove(path);
}

TEST(VtkTetIo, BadFilesAreInputErrorsNamingTheFile) {
  expect_error("/no/such/file.vtu", {}, "does not exist");
  const std::string garbage = temp_path("garbage.vtu");
  std::ofstream(garbage) << "this is not XML at all";
  expect_error(garbage, {}, "not a VTK XML unstructured grid");
  const std::string legacy_garbage = temp_path("garbage.vtk");
  std::ofstream(legacy_garbage) << "hello\n";
  expect_error(legacy_garbage, {}, "legacy VTK");
  const std::string wrong_ext = temp_path("mesh.xyz");
  std::ofstream(wrong_ext) << "1 2 3\n";
  expect_error(wrong_ext, {}, "unknown dataset type");
  const std::string negative = temp_path("negative.vtk");
  std::ofstream(negative) << "# vtk DataFile Version 3.0\ntet\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 double\n"
                             "0 0 0 1 0 0 0 1 0 0 0 1\nCELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n"
                             "CELL_DATA 1\nSCALARS sigma double 1\nLOOKUP_TABLE default\n-1\n";
  expect_error(negative, {.array = "sigma"}, "must be finite and >= 0");
  for (const auto& p : {garbage, legacy_garbage, wrong_ext, negative}) std::filesystem::remove(p);
}

}  // namespace
}  // namespace prismoid
