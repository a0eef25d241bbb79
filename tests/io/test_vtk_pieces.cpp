// Meshes in several pieces: a multiblock .vtm and a parallel .pvtu become one mesh whose
// pieces share their boundary points, so the split stays conforming across pieces.
#include <gtest/gtest.h>

#include "support/mesh_faces.hpp"

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkXMLMultiBlockDataWriter.h>

#include "io/dataset_info.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_quality.hpp"
#include "vtk_test_grids.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;
using testgrids::Cut;

fs::path scratch() {
  const fs::path d = fs::temp_directory_path() / ("prismoid_pieces_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// Two boxes of 2^3 cubes side by side along x: [0, wx] and [wx, 2 wx], written separately
// so the points of their shared face exist twice, with unrelated ids.
struct TwoBoxes {
  testgrids::Lattice left = testgrids::make_lattice(2);
  testgrids::Lattice right = testgrids::make_lattice(2, left.xs.back());
  vtkSmartPointer<vtkUnstructuredGrid> a = testgrids::make_grid(left, Cut::Hexahedra, 11);
  vtkSmartPointer<vtkUnstructuredGrid> b = testgrids::make_grid(right, Cut::Mixed, 12);
  // Shared face: (n+1)^2 corners; the cube centres are never shared.
  static constexpr size_t kSharedPoints = 9;
};

size_t interior_faces_unshared(const TetMesh& mesh, double x_min, double x_max) {
  // Counts triangles used by one tetrahedron that are not on the outer boundary x = min or
  // max, y, z = their extremes: a crack across the pieces' common face would show up here.
  const std::map<std::array<uint32_t, 3>, int> count = test::face_uses(mesh);
  const Bounds b = bounds_of(mesh);
  EXPECT_EQ(b.min.x, x_min);
  EXPECT_EQ(b.max.x, x_max);
  size_t cracks = 0;
  for (const auto& [f, n] : count) {
    if (n != 1) continue;
    bool on_boundary = false;
    for (int axis = 0; axis < 3; ++axis)
      for (double plane : {b.min[axis], b.max[axis]})
        on_boundary = on_boundary || (mesh.points[f[0]][axis] == plane && mesh.points[f[1]][axis] == plane && mesh.points[f[2]][axis] == plane);
    if (!on_boundary) ++cracks;
  }
  return cracks;
}

void expect_merged(const TetMesh& mesh, const io::MeshConversion& report, const TwoBoxes& boxes) {
  EXPECT_EQ(report.pieces, 2u);
  EXPECT_EQ(report.merged_points, TwoBoxes::kSharedPoints);
  EXPECT_EQ(mesh.points.size(), size_t(boxes.a->GetNumberOfPoints() + boxes.b->GetNumberOfPoints()) - TwoBoxes::kSharedPoints);
  EXPECT_EQ(interior_faces_unshared(mesh, boxes.left.xs.front(), boxes.right.xs.back()), 0u);
  const double volume = boxes.left.volume() + boxes.right.volume();
  EXPECT_NEAR(tet_quality(mesh).total_volume, volume, 1e-12 * volume);  // rounding of a few hundred terms
  // The cell array survives the merge: every cell_id value is an index into its own piece.
  ASSERT_EQ(mesh.cell_scalars.size(), mesh.tets.size());
  for (double v : mesh.cell_scalars) EXPECT_LT(v, double(std::max(boxes.a->GetNumberOfCells(), boxes.b->GetNumberOfCells())));
}

TEST(VtkPieces, MultiblockBlocksAreMergedConforming) {
  TwoBoxes boxes;
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetNumberOfBlocks(2);
  blocks->SetBlock(0, boxes.a);
  blocks->SetBlock(1, boxes.b);
  const std::string path = (scratch() / "two.vtm").string();
  vtkNew<vtkXMLMultiBlockDataWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(blocks);
  ASSERT_EQ(writer->Write(), 1);
  io::MeshConversion report;
  const TetMesh mesh = io::read_tet_mesh(path, {.array = "cell_id", .role = io::ArrayRole::Scalars}, &report);
  expect_merged(mesh, report, boxes);
  EXPECT_NE(io::conversion_note(report).find("merged 2 pieces (9 shared points)"), std::string::npos) << io::conversion_note(report);
}

TEST(VtkPieces, MultiblockWithAnImageBlockNamesIt) {
  TwoBoxes boxes;
  vtkNew<vtkImageData> image;
  image->SetDimensions(2, 2, 2);
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetNumberOfBlocks(2);
  blocks->SetBlock(0, boxes.a);
  blocks->SetBlock(1, image);
  blocks->GetMetaData(1u)->Set(vtkCompositeDataSet::NAME(), "density");
  const std::string path = (scratch() / "image.vtm").string();
  vtkNew<vtkXMLMultiBlockDataWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(blocks);
  ASSERT_EQ(writer->Write(), 1);
  // Drawn without it, and a note names it and why.
  io::MeshConversion report;
  const TetMesh mesh = io::read_tet_mesh(path, {}, &report);
  EXPECT_EQ(mesh.points.size(), size_t(boxes.a->GetNumberOfPoints()));
  EXPECT_NE(io::conversion_note(report).find("not drawn: block 1 'density' (is a vtkImageData, not an unstructured grid"), std::string::npos)
      << io::conversion_note(report);
  // `info` lists both.
  const io::DatasetInfo info = io::describe_dataset(path);
  EXPECT_EQ(info.blocks, (std::vector<std::string>{"block 0: " + std::to_string(boxes.a->GetNumberOfCells()) + " cells",
                                                   "block 1 'density': vtkImageData (not drawn)"}));
  // Chosen by name: refused, saying why.
  for (const char* block : {"density", "1"})
    try {
      io::read_tet_mesh(path, {.blocks = {block}});
      ADD_FAILURE() << "an image block is not an unstructured grid";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("block 1 'density' is a vtkImageData, not an unstructured grid"), std::string::npos) << e.what();
    }
}

// Blocks picked by index or name: the chosen ones only, merged; a name that is no block is
// refused listing the blocks there are.
TEST(VtkPieces, MultiblockBlocksAreChosenByIndexOrName) {
  TwoBoxes boxes;
  vtkNew<vtkMultiBlockDataSet> blocks;
  blocks->SetNumberOfBlocks(2);
  blocks->SetBlock(0, boxes.a);
  blocks->SetBlock(1, boxes.b);
  blocks->GetMetaData(0u)->Set(vtkCompositeDataSet::NAME(), "left");
  blocks->GetMetaData(1u)->Set(vtkCompositeDataSet::NAME(), "right");
  const std::string path = (scratch() / "named.vtm").string();
  vtkNew<vtkXMLMultiBlockDataWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(blocks);
  ASSERT_EQ(writer->Write(), 1);
  const TetMesh left = io::read_tet_mesh(path, {.blocks = {"left"}});
  EXPECT_EQ(left.points.size(), size_t(boxes.a->GetNumberOfPoints()));
  const TetMesh right = io::read_tet_mesh(path, {.blocks = {"1"}});
  EXPECT_EQ(right.points.size(), size_t(boxes.b->GetNumberOfPoints()));
  io::MeshConversion report;
  const TetMesh both = io::read_tet_mesh(path, {.array = "cell_id", .role = io::ArrayRole::Scalars, .blocks = {"right", "0"}}, &report);
  expect_merged(both, report, boxes);
  try {
    io::read_tet_mesh(path, {.blocks = {"middle"}});
    ADD_FAILURE() << "no block is named middle";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'middle' names no block of " + path + " (its blocks, by index and name: 0 'left' (vtkUnstructuredGrid), 1 'right' (vtkUnstructuredGrid))"),
              std::string::npos) << e.what();
  }
}

// A .pvtu names its pieces' .vtu files and declares the arrays they hold.
void write_pvtu(const fs::path& path, const std::vector<std::string>& pieces) {
  std::ofstream out(path);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData>\n"
         "<PDataArray type=\"Float64\" Name=\"height\"/>\n<PDataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\"/>\n"
         "</PPointData>\n<PCellData>\n<PDataArray type=\"Float64\" Name=\"cell_id\"/>\n</PCellData>\n"
         "<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
  for (const auto& p : pieces) out << "<Piece Source=\"" << p << "\"/>\n";
  out << "</PUnstructuredGrid>\n</VTKFile>\n";
}

TEST(VtkPieces, ParallelPiecesAreMergedConforming) {
  TwoBoxes boxes;
  const fs::path dir = scratch();
  testgrids::write_vtu((dir / "p0.vtu").string(), boxes.a);
  testgrids::write_vtu((dir / "p1.vtu").string(), boxes.b);
  write_pvtu(dir / "two.pvtu", {"p0.vtu", "p1.vtu"});
  io::MeshConversion report;
  const TetMesh mesh = io::read_tet_mesh((dir / "two.pvtu").string(), {.array = "cell_id", .role = io::ArrayRole::Scalars}, &report);
  expect_merged(mesh, report, boxes);
}

TEST(VtkPieces, ParallelFileWithAMissingPieceIsAnInputError) {
  TwoBoxes boxes;
  const fs::path dir = scratch();
  testgrids::write_vtu((dir / "q0.vtu").string(), boxes.a);
  write_pvtu(dir / "missing.pvtu", {"q0.vtu", "no_such_piece.vtu"});
  try {
    io::read_tet_mesh((dir / "missing.pvtu").string());
    ADD_FAILURE() << "a piece is missing";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("piece 1 cannot be read"), std::string::npos) << e.what();
  }
}

class RemoveScratch : public ::testing::Environment {
 public:
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(scratch(), ignored);
  }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new RemoveScratch);

}  // namespace
}  // namespace prismoid
