// Progress while VTK reads and converts: fractions rise monotonically to 1, and a callback that
// says stop makes the read throw Cancelled without leaving anything behind.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "io/image_volume_io.hpp"
#include "io/surface_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/generators.hpp"
#include "vtk_test_grids.hpp"

#include <vtkImageData.h>
#include <vtkXMLImageDataWriter.h>

namespace prismoid {
namespace {

namespace fs = std::filesystem;

// A folder of its own per test, so "nothing left behind" can be checked by listing it.
class VtkProgress : public ::testing::Test {
 protected:
  // 60^3 cubes of six tetrahedra: 1,296,000 cells, large enough that VTK reports many times;
  // written once for the suite.
  static void SetUpTestSuite() {
    big_vtu_ = (fs::temp_directory_path() / ("prismoid_progress_big_" + std::to_string(::getpid()) + ".vtu")).string();
    io::write_tet_mesh_vtu(big_vtu_, make_box_mesh(glm::dvec3(0.0), glm::dvec3(1.0), 60, [](const glm::dvec3& p) { return p.x; }));
  }
  static void TearDownTestSuite() { fs::remove(big_vtu_); }
  static constexpr size_t kBigCells = 6 * 60 * 60 * 60;
  static inline std::string big_vtu_;

  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("prismoid_progress_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  size_t files() const { return size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())); }
  fs::path dir_;
};

struct Recorder {
  std::vector<double> fractions;
  std::vector<std::string> stages;
  io::Progress callback() {
    return [this](double f, const std::string& stage) {
      fractions.push_back(f);
      if (stages.empty() || stages.back() != stage) stages.push_back(stage);
      return true;
    };
  }
  void expect_monotone_to_one() const {
    ASSERT_FALSE(fractions.empty());
    for (size_t i = 0; i < fractions.size(); ++i) {
      EXPECT_GE(fractions[i], 0.0) << i;
      EXPECT_LE(fractions[i], 1.0) << i;
      if (i > 0) {
        EXPECT_GE(fractions[i], fractions[i - 1]) << "report " << i << " goes back";
      }
    }
    EXPECT_EQ(fractions.back(), 1.0);
  }
};

TEST_F(VtkProgress, ReadingAMillionCellVtuReportsRisingFractionsEndingAtOne) {
  Recorder r;
  const TetMesh mesh = io::read_tet_mesh(big_vtu_, {.progress = r.callback()});
  EXPECT_EQ(mesh.tets.size(), kBigCells);
  r.expect_monotone_to_one();
  EXPECT_GT(r.fractions.size(), 10u) << "VTK's reader should report along the way, not only at its ends";
}

TEST_F(VtkProgress, SplittingHexahedraIsReportedAsItsOwnStage) {
  const std::string file = path("hex.vtu");
  testgrids::write_vtu(file, testgrids::make_grid(testgrids::make_lattice(12), testgrids::Cut::Hexahedra));
  Recorder r;
  io::read_tet_mesh(file, {.progress = r.callback()});
  r.expect_monotone_to_one();
  EXPECT_NE(std::find(r.stages.begin(), r.stages.end(), "splitting cells into tetrahedra"), r.stages.end());
}

TEST_F(VtkProgress, ACallbackSayingStopCancelsTheReadAndLeavesNothing) {
  // Stop at the first report inside VTK's read (neither end of the span): the reader aborts.
  int calls = 0, calls_after_stop = 0;
  bool stopped = false;
  auto stop_midway = [&](double f, const std::string&) {
    ++calls;
    if (stopped) ++calls_after_stop;
    if (f > 0.0 && f < 0.7) stopped = true;
    return !stopped;
  };
  const fs::file_time_type written = fs::last_write_time(big_vtu_);
  EXPECT_THROW(io::read_tet_mesh(big_vtu_, {.progress = stop_midway}), io::Cancelled);
  EXPECT_TRUE(stopped);
  EXPECT_EQ(calls_after_stop, 0) << "no reports after the callback said stop";
  EXPECT_EQ(fs::last_write_time(big_vtu_), written);
  for (const auto& entry : fs::directory_iterator(fs::path(big_vtu_).parent_path()))
    EXPECT_TRUE(entry.path() == big_vtu_ || entry.path().string().rfind(big_vtu_, 0) != 0) << "left behind: " << entry.path();
  // The same file reads normally afterwards (nothing process-wide stayed aborted).
  EXPECT_EQ(io::read_tet_mesh(big_vtu_).tets.size(), kBigCells);
}

TEST_F(VtkProgress, ImageReadsReportWhileVtkReadsAndCancelThere) {
  const std::string file = path("cube.vti");
  {
    vtkNew<vtkImageData> image;
    image->SetDimensions(64, 64, 64);
    vtkNew<vtkDoubleArray> density;
    density->SetName("density");
    density->SetNumberOfValues(64 * 64 * 64);
    for (vtkIdType i = 0; i < density->GetNumberOfValues(); ++i) density->SetValue(i, double(i % 7));
    image->GetPointData()->SetScalars(density);
    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetFileName(file.c_str());
    writer->SetInputData(image);
    ASSERT_EQ(writer->Write(), 1);
  }
  Recorder r;
  io::ImageReadOptions options;
  options.progress = r.callback();
  io::read_image_volume(file, options);
  r.expect_monotone_to_one();
  EXPECT_NE(std::find(r.stages.begin(), r.stages.end(), "reading voxels"), r.stages.end());
  // Stopping inside VTK's read (the first half of the bar) cancels there.
  options.progress = [](double f, const std::string& stage) { return !(stage == "reading voxels" && f > 0.0); };
  EXPECT_THROW(io::read_image_volume(file, options), io::Cancelled);
  EXPECT_EQ(files(), 1u);
}

TEST_F(VtkProgress, SurfaceReadsReportAndCancel) {
  const std::string off = path("tet.off");
  std::ofstream(off) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  Recorder r;
  EXPECT_EQ(io::read_surface(off, r.callback()).triangles.size(), 4u);
  r.expect_monotone_to_one();
  EXPECT_THROW(io::read_surface(off, [](double, const std::string&) { return false; }), io::Cancelled);
}

}  // namespace
}  // namespace prismoid
