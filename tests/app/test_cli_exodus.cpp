// End-to-end: Exodus II files as a user opens them. The files are written with the Exodus library
// itself (support/exodus_file.hpp); what `info`, `render` and `convert` make of them is held to
// the values written, to the closed form of the optical depth and to the CPU reference, never to
// Prismoid's own earlier output.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "io/image_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/camera.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "support/box_view.hpp"
#include "support/cli_run.hpp"
#include "support/exodus_file.hpp"
#include "support/time_sweep_rows.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::ExodusBlockSpec;
using test::ExodusFileSpec;
using test::cli::run;
using test::cli::work_dir;

constexpr uint32_t kSide = test::kBoxViewSide;
Camera view() { return test::box_view(); }
const std::string kView = test::kBoxViewArgs + " --quantity optical-depth --array extinction";

double centre(const io::FloatImage& img) { return test::box_view_centre(img.pixels); }

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = work_dir() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The box [-1,1]^3 with an extinction that varies from cell to cell.
TetMesh varying_box() {
  return make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 3, [](const glm::dvec3& p) { return 0.5 + 0.25 * (p.x + 1.0) + 0.1 * (p.y + 1.0); });
}

// One mesh, written as a .vtu and as an Exodus file (one TETRA block, the extinction an element
// variable of its one step): both render the CPU reference's image of that mesh, and each other's.
TEST(CliExodus, TheSameMeshAsVtuAndAsExodusRendersTheSameImage) {
  const fs::path dir = fresh_dir("exodus_same");
  const TetMesh mesh = varying_box();
  io::write_tet_mesh_vtu((dir / "box.vtu").string(), mesh);
  ExodusFileSpec spec = test::exodus_of(mesh);
  spec.element_variables = {"extinction"};
  spec.times = {0.0};
  spec.blocks[0].values = {{mesh.cell_extinction}};
  test::write_exodus(dir / "box.exo", spec);

  const std::vector<double> ref = reference::optical_depth_image(mesh, view(), kSide, kSide);
  std::vector<io::FloatImage> images;
  for (const std::string file : {"box.vtu", "box.exo"}) {
    const fs::path pfm = dir / (file + ".pfm");
    const CliRun r = run("render " + (dir / file).string() + kView + " --validate --output " + pfm.string());
    ASSERT_EQ(r.code, 0) << file << ": " << r.err;
    images.push_back(io::read_pfm(pfm.string()));
    ASSERT_EQ(images.back().pixels.size(), ref.size());
    for (size_t p = 0; p < ref.size(); ++p) EXPECT_NEAR(images.back().pixels[p], ref[p], 1e-4 * (1.0 + ref[p])) << file << " pixel " << p;
  }
  // The same cells in the same order: the same float arithmetic, within a float's rounding.
  for (size_t p = 0; p < ref.size(); ++p) EXPECT_NEAR(images[0].pixels[p], images[1].pixels[p], 1e-6 * (1.0 + ref[p])) << "pixel " << p;
}

// Three steps of the box, each of one constant extinction (an element variable).
const std::vector<double> kSigma = {0.5, 1.0, 2.0}, kTimes = {0.0, 0.5, 1.5};
TetMesh steps_box() { return make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 2, [](const glm::dvec3&) { return 1.0; }); }
fs::path write_steps(const fs::path& dir) {
  const TetMesh mesh = steps_box();
  ExodusFileSpec spec = test::exodus_of(mesh, 7);
  spec.element_variables = {"extinction"};
  spec.times = kTimes;
  for (double s : kSigma) spec.blocks[0].values.push_back({std::vector<double>(mesh.tets.size(), s)});
  const fs::path exo = dir / "steps.e";
  test::write_exodus(exo, spec);
  return exo;
}

// `info` lists the steps, and each step drawn gives 2 sigma of its own step along the axis.
TEST(CliExodus, EachStepGivesItsOwnClosedFormOpticalDepth) {
  const fs::path dir = fresh_dir("exodus_steps");
  const fs::path exo = write_steps(dir);
  const std::vector<double>& sigma = kSigma;
  const TetMesh mesh = steps_box();

  const CliRun info = run("info " + exo.string());
  ASSERT_EQ(info.code, 0) << info.err;
  for (const std::string& line : std::vector<std::string>{"(Exodus II: 1 element block, 3 time steps;", "block 7: " + std::to_string(mesh.tets.size()) + " vtkTetra",
                                 "element variables (cell arrays): extinction", "step 0: t = 0\n", "step 1: t = 0.5\n", "step 2: t = 1.5\n"})
    EXPECT_NE(info.out.find(line), std::string::npos) << line << " in\n" << info.out;
  for (size_t i = 0; i < sigma.size(); ++i) {
    const fs::path pfm = dir / ("step" + std::to_string(i) + ".pfm");
    const CliRun r = run("render " + exo.string() + " --time-step " + std::to_string(i) + kView + " --output " + pfm.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("step " + std::to_string(i) + " (t = "), std::string::npos) << r.out;
    EXPECT_NEAR(centre(io::read_pfm(pfm.string())), 2.0 * sigma[i], 1e-5 * 2.0 * sigma[i]) << "step " << i;
  }
  const fs::path at = dir / "at.pfm";
  CliRun r = run("render " + exo.string() + " --time 0.7" + kView + " --output " + at.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(centre(io::read_pfm(at.string())), 2.0 * sigma[1], 1e-5 * 2.0 * sigma[1]);
  r = run("render " + exo.string() + kView + " --output " + at.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("3 time steps; drawing step 0 (t = 0)"), std::string::npos) << r.err;
  EXPECT_NEAR(centre(io::read_pfm(at.string())), 2.0 * sigma[0], 1e-5 * 2.0 * sigma[0]);
}

// The bench's time sweep over an Exodus file's steps: each step's transmittance and colour, and
// the step switches (each step whole, or its fields alone), each held to its own step's reference
// (against another step's, transmittance would be off by tenths).
TEST(CliExodus, TheBenchTimesEveryStep) {
  const fs::path dir = fresh_dir("exodus_bench");
  const fs::path exo = write_steps(dir);
  const CliRun r = run("bench " + exo.string() + " --quick --sweeps time --no-plots --no-peers --array extinction --out " + (dir / "b").string());
  ASSERT_EQ(r.code, 0) << r.err;
  test::expect_time_sweep_rows(dir / "b" / "bench.csv", kSigma.size());
}

// A hexahedron (block 10 'fluid') and a tetrahedron (block 20) sharing a face's three nodes, a
// quadrilateral (block 30) and a node set: the 3D blocks are drawn by default and merged on their
// shared nodes, the rest named in a note; --blocks picks by id or name; element variables become
// cell arrays and nodal ones point arrays, with the values written.
ExodusFileSpec blocks_file() {
  ExodusFileSpec spec;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i) spec.points.emplace_back(i, j, k);
  const auto n = [](int i, int j, int k) { return int64_t(i + 3 * j + 6 * k); };
  ExodusBlockSpec hex{10, "fluid", "HEX8", 8, {n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(0, 1, 0), n(0, 0, 1), n(1, 0, 1), n(1, 1, 1), n(0, 1, 1)}, {}};
  ExodusBlockSpec tet{20, "", "TETRA", 4, {n(1, 0, 0), n(2, 0, 0), n(1, 1, 0), n(1, 0, 1)}, {}};
  ExodusBlockSpec quad{30, "", "QUAD4", 4, {n(0, 0, 0), n(1, 0, 0), n(1, 1, 0), n(0, 1, 0)}, {}};
  hex.values = {{{3.0}}};
  tet.values = {{{5.0}}};
  quad.values = {{{7.0}}};
  spec.blocks = {hex, tet, quad};
  spec.times = {0.25};
  spec.element_variables = {"pressure"};
  spec.nodal_variables = {"temperature"};
  std::vector<double> temperature;
  for (const glm::dvec3& p : spec.points) temperature.push_back(p.x + 10.0 * p.y + 100.0 * p.z);
  spec.nodal_values = {{temperature}};
  spec.node_sets = {{0, 1}};
  return spec;
}

TEST(CliExodus, BlocksAreListedChosenAndMergedWithTheirVariables) {
  const fs::path dir = fresh_dir("exodus_blocks");
  const fs::path exo = dir / "blocks.exo";
  test::write_exodus(exo, blocks_file());
  const CliRun info = run("info " + exo.string());
  ASSERT_EQ(info.code, 0) << info.err;
  for (const std::string& line : std::vector<std::string>{"(Exodus II: 3 element blocks, 1 time step;", "block 10 'fluid': 1 vtkHexahedron\n", "block 20: 1 vtkTetra\n",
                                 "block 30: 1 vtkQuad (no 3D cells: not drawn)", "nodal variables (point arrays): temperature",
                                 "node sets: 1, side sets: 0 (not drawn)"})
    EXPECT_NE(info.out.find(line), std::string::npos) << line << " in\n" << info.out;

  // convert writes what was read: the tetrahedra, their extinction (here the element variable)
  // and the point scalars (the nodal variable).
  const auto converted = [&](const std::string& options, const std::string& array, CliRun* out = nullptr) {
    const fs::path vtu = dir / "out.vtu";
    fs::remove(vtu);
    const CliRun r = run("convert " + exo.string() + " " + vtu.string() + " --array " + array + options);
    EXPECT_EQ(r.code, 0) << options << ": " << r.err;
    if (out) *out = r;
    io::TetReadOptions reading;
    reading.array = array == "temperature" ? "scalars" : "extinction";
    return r.code == 0 ? io::read_tet_mesh(vtu.string(), reading) : TetMesh{};
  };
  CliRun r;
  TetMesh both = converted("", "pressure", &r);
  EXPECT_NE(r.err.find("not drawn: block 30 (vtkQuad: no 3D cells)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("not drawn: 1 node set"), std::string::npos) << r.err;
  EXPECT_EQ(both.tets.size(), 7u);    // the hexahedron's 6 and the tetrahedron
  EXPECT_EQ(both.points.size(), 9u);  // 8 + 4, the 3 shared nodes once
  // Each block's element variable on its own cells: the hexahedron's 6 tetrahedra and the one.
  EXPECT_EQ(std::count(both.cell_extinction.begin(), both.cell_extinction.end(), 3.0), 6);
  EXPECT_EQ(std::count(both.cell_extinction.begin(), both.cell_extinction.end(), 5.0), 1);
  const TetMesh tet_only = converted(" --blocks 20", "pressure");
  EXPECT_EQ(tet_only.tets.size(), 1u);
  const TetMesh hex_only = converted(" --blocks fluid", "pressure");
  EXPECT_EQ(hex_only.tets.size(), 6u);
  EXPECT_EQ(converted(" --blocks ' fluid , 20'", "pressure").tets.size(), 7u);
  const TetMesh hot = converted("", "temperature");
  ASSERT_EQ(hot.point_scalars.size(), hot.points.size());
  for (size_t i = 0; i < hot.points.size(); ++i) {
    const glm::dvec3& p = hot.points[i];
    EXPECT_DOUBLE_EQ(hot.point_scalars[i], p.x + 10.0 * p.y + 100.0 * p.z) << "point " << i;
  }
}

// The careless and the hostile Exodus file, and choices that do not exist: exit 2, naming the
// file (or the option) and the problem; no image written.
TEST(CliExodus, BadFilesAndChoicesAreRefusedByName) {
  const fs::path dir = fresh_dir("exodus_bad");
  const fs::path png = dir / "o.png";
  const auto refused = [&](const std::string& args, const std::string& says) {
    const CliRun r = run("render " + args + " --size 8x8 --output " + png.string());
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(png)) << args;
  };
  const fs::path good = dir / "good.exo";
  test::write_exodus(good, blocks_file());
  refused(good.string() + " --blocks 99", "--blocks: '99' names no element block of " + good.string() + " (its blocks, by id and name: 10 'fluid', 20, 30)");
  refused(good.string() + " --blocks 30", "block 30 holds vtkQuad cells, no 3D cells: it cannot be drawn as a volume");
  refused(good.string() + " --blocks 10,,20", "--blocks: '10,,20' holds an empty block name");
  refused(good.string() + " --time-step 1", "--time-step: " + good.string() + " has 1 steps (0 to 0), not 1");
  refused(good.string() + " --time 3", "--time: 3 lies outside");

  ExodusFileSpec flat = blocks_file();
  flat.blocks.erase(flat.blocks.begin(), flat.blocks.begin() + 2);  // the quadrilateral alone
  test::write_exodus(dir / "flat.exo", flat);
  refused((dir / "flat.exo").string(), "has no element block with 3D cells (its blocks: 30 (vtkQuad))");

  ExodusFileSpec timeless = blocks_file();
  timeless.times.clear();
  test::write_exodus(dir / "timeless.exo", timeless);
  refused((dir / "timeless.exo").string() + " --time-step 0", "--time-step: " + (dir / "timeless.exo").string() + " holds no time steps");

  ExodusFileSpec nan = blocks_file();
  nan.times = {0.0, std::numeric_limits<double>::quiet_NaN()};
  test::write_exodus(dir / "nan.exo", nan);
  refused((dir / "nan.exo").string(), "time step 1 has the time value nan, not a finite number");
  ExodusFileSpec back = blocks_file();
  back.times = {1.0, 0.5};
  test::write_exodus(dir / "back.exo", back);
  refused((dir / "back.exo").string(), "time step 1 (t = 0.5) does not come after step 0 (t = 1): time values must increase");

  std::ofstream(dir / "text.exo") << "not an Exodus file\n";
  refused((dir / "text.exo").string(), "is not an Exodus II file");
  // Cut short: within its header, and within its data (netCDF would read the missing values as
  // zeros, the time values among them).
  const std::string bytes = test::slurp(good);
  for (const size_t keep : {bytes.size() / 8, bytes.size() - 16}) {
    const fs::path cut = dir / ("cut" + std::to_string(keep) + ".exo");
    std::ofstream(cut, std::ios::binary) << bytes.substr(0, keep);
    refused(cut.string(), "the file is truncated or corrupt");
  }
  const fs::path vtu = dir / "box.vtu";
  io::write_tet_mesh_vtu(vtu.string(), varying_box());
  refused(vtu.string() + " --blocks 1", "--blocks: picks blocks of a multiblock .vtm or an Exodus II file");
}

}  // namespace
}  // namespace prismoid
