// End-to-end: a time series (.pvd) as a user opens one: `info` lists its steps, `render` draws the
// step --time-step or --time picks, held to the closed form of each step's optical depth, and bad
// collections are refused naming the file and the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
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
#include "support/time_sweep_rows.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::cli::run;
using test::cli::work_dir;

// Three steps of the box [-1,1]^3, each of one constant extinction.
const std::vector<double> kSigma = {0.5, 1.0, 2.0};
const std::vector<double> kTimes = {0.0, 0.5, 1.5};

TetMesh box(double sigma) {
  return make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 2, [sigma](const glm::dvec3&) { return sigma; });
}

// A collection of `entries` (timestep, file) in `dir`, as ParaView writes one.
fs::path write_pvd(const fs::path& dir, const std::string& name, const std::vector<std::pair<std::string, std::string>>& entries) {
  const fs::path pvd = dir / name;
  std::ofstream out(pvd);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const auto& [time, file] : entries) out << "    <DataSet timestep=\"" << time << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
  out << "  </Collection>\n</VTKFile>\n";
  return pvd;
}

// The series of the three boxes, their meshes in a folder beside the collection.
fs::path write_series(const fs::path& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir / "steps");
  std::vector<std::pair<std::string, std::string>> entries;
  for (size_t i = 0; i < kSigma.size(); ++i) {
    const std::string file = "steps/box_" + std::to_string(i) + ".vtu";
    io::write_tet_mesh_vtu((dir / file).string(), box(kSigma[i]));
    std::ostringstream t;
    t << kTimes[i];
    entries.emplace_back(t.str(), file);
  }
  return write_pvd(dir, "boxes.pvd", entries);
}

constexpr uint32_t kSide = test::kBoxViewSide;
Camera view() { return test::box_view(); }
const std::string kView = test::kBoxViewArgs + " --quantity optical-depth --array extinction";

// Each step drawn is that step: the centre pixel's optical depth is its extinction times the
// box's chord of 2 (float32 and the GPU's interval arithmetic: within 1e-5 relative), and the
// whole image is the CPU reference's of that step's mesh.
TEST(CliTimeSeries, EachStepGivesItsOwnClosedFormOpticalDepth) {
  const fs::path dir = work_dir() / "series";
  const fs::path pvd = write_series(dir);
  const CliRun info = run("info " + pvd.string());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("(time series, 3 steps;"), std::string::npos) << info.out;
  for (size_t i = 0; i < kTimes.size(); ++i) {
    std::ostringstream line;
    line << "  step " << i << ": t = " << kTimes[i] << ", ";
    EXPECT_NE(info.out.find(line.str()), std::string::npos) << line.str() << " in\n" << info.out;
  }
  EXPECT_NE(info.out.find("step 0: "), std::string::npos) << info.out;

  const auto centre = [](const io::FloatImage& img) { return double(img.pixels[(kSide / 2) * kSide + kSide / 2]); };
  for (size_t i = 0; i < kSigma.size(); ++i) {
    const fs::path pfm = dir / ("step" + std::to_string(i) + ".pfm");
    const CliRun r = run("render " + pvd.string() + " --time-step " + std::to_string(i) + kView + " --validate --output " + pfm.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("step " + std::to_string(i) + " (t = "), std::string::npos) << r.out;
    const io::FloatImage img = io::read_pfm(pfm.string());
    EXPECT_NEAR(centre(img), 2.0 * kSigma[i], 1e-5 * 2.0 * kSigma[i]) << "step " << i;
    const std::vector<double> ref = reference::optical_depth_image(box(kSigma[i]), view(), kSide, kSide);
    ASSERT_EQ(ref.size(), img.pixels.size());
    for (size_t p = 0; p < ref.size(); ++p) EXPECT_NEAR(img.pixels[p], ref[p], 1e-4 * (1.0 + ref[p])) << "step " << i << " pixel " << p;
  }
  // --time picks the last step at or before it; none picked: the first, with a note.
  const fs::path at = dir / "at.pfm";
  CliRun r = run("render " + pvd.string() + " --time 0.7" + kView + " --output " + at.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(centre(io::read_pfm(at.string())), 2.0 * kSigma[1], 1e-5 * 2.0 * kSigma[1]);
  r = run("render " + pvd.string() + " --time 1.5" + kView + " --output " + at.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NEAR(centre(io::read_pfm(at.string())), 2.0 * kSigma[2], 1e-5 * 2.0 * kSigma[2]);
  r = run("render " + pvd.string() + kView + " --output " + at.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("a time series of 3 steps; drawing step 0 (t = 0)"), std::string::npos) << r.err;
  EXPECT_NEAR(centre(io::read_pfm(at.string())), 2.0 * kSigma[0], 1e-5 * 2.0 * kSigma[0]);
}

// The careless and the hostile collection, and steps that do not exist: exit 2, naming the
// collection (or the option) and the problem; no image written.
TEST(CliTimeSeries, BadCollectionsAndStepsAreRefusedByName) {
  const fs::path dir = work_dir() / "bad_series";
  const fs::path good = write_series(dir);
  io::write_tet_mesh_vtu((work_dir() / "outside.vtu").string(), box(1.0));
  const fs::path png = dir / "o.png";
  const auto refused = [&](const std::string& args, const std::string& says) {
    const CliRun r = run("render " + args + " --size 8x8 --output " + png.string());
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(png)) << args;
  };
  const auto pvd = [&](const std::string& name, const std::vector<std::pair<std::string, std::string>>& entries) {
    return write_pvd(dir, name, entries).string();
  };
  refused(pvd("missing.pvd", {{"0", "steps/box_0.vtu"}, {"1", "steps/nothing.vtu"}}), "step 1 (t = 1, steps/nothing.vtu): file does not exist");
  refused(pvd("outside.pvd", {{"0", "../outside.vtu"}}), "lies outside the collection's folder");
  refused(pvd("absolute.pvd", {{"0", (work_dir() / "outside.vtu").string()}}), "lies outside the collection's folder");
  refused(pvd("self.pvd", {{"0", "self.pvd"}}), "is a collection itself");
  refused(pvd("nan.pvd", {{"nan", "steps/box_0.vtu"}}), "timestep 'nan' is not a finite number");
  refused(pvd("word.pvd", {{"soon", "steps/box_0.vtu"}}), "timestep 'soon' is not a number");
  refused(pvd("back.pvd", {{"1", "steps/box_0.vtu"}, {"0.5", "steps/box_1.vtu"}}), "times must increase");
  refused(pvd("parts.pvd", {{"0", "steps/box_0.vtu"}, {"0", "steps/box_1.vtu"}}), "several parts at one time are not read");
  refused(pvd("empty.pvd", {}), "holds no data set");
  refused(pvd("surface.pvd", {{"0", "steps/box_0.stl"}}), "is not a mesh file a time step can be");
  {
    const fs::path not_xml = dir / "garbage.pvd";
    std::ofstream(not_xml) << "this is not XML <<<";
    refused(not_xml.string(), "its XML does not parse");
    const fs::path other = dir / "other.pvd";
    std::ofstream(other) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\"></VTKFile>\n";
    refused(other.string(), "is not a ParaView data collection");
  }
  refused(good.string() + " --time-step 3", "--time-step: " + good.string() + " has 3 steps (0 to 2), not 3");
  refused(good.string() + " --time 5", "--time: 5 lies outside");
  refused(good.string() + " --time -1", "--time: -1 lies outside");
  refused(good.string() + " --time-step 1 --time 0.5", "both pick a step");
  refused((dir / "steps" / "box_0.vtu").string() + " --time-step 0", "--time-step: picks a step of a time series (.pvd, 'name_*.vtu') or an Exodus II file");
  // No output may replace a step the command reads through the series: refused before any work,
  // the step keeping its bytes.
  const fs::path step0 = dir / "steps" / "box_0.vtu";
  const auto size_before = fs::file_size(step0);
  for (const std::string& series : {good.string(), "'" + (dir / "steps" / "box_*.vtu").string() + "'"}) {
    const CliRun r = run("convert " + series + " " + step0.string());
    EXPECT_EQ(r.code, 2) << series << ": " << r.err;
    EXPECT_NE(r.err.find("would write over a file this command reads"), std::string::npos) << series << ": " << r.err;
    EXPECT_EQ(fs::file_size(step0), size_before);
  }
}

// A numbered series (flow_*.vtu, as ParaView groups such files): the files in the order of their
// numbers, not of their names (flow_9 before flow_10), each at the time of its index; the bad
// patterns are refused naming the pattern.
TEST(CliTimeSeries, ANumberedSeriesIsItsFilesInTheOrderOfTheirNumbers) {
  const fs::path dir = work_dir() / "numbered";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // Steps 9, 10 and 100: by name 10 < 100 < 9; by number 9 < 10 < 100.
  const std::vector<std::string> names = {"flow_10.vtu", "flow_100.vtu", "flow_9.vtu"};
  const std::vector<double> sigma = {1.0, 2.0, 0.5};  // flow_10, flow_100, flow_9
  for (size_t i = 0; i < names.size(); ++i) io::write_tet_mesh_vtu((dir / names[i]).string(), box(sigma[i]));
  std::ofstream(dir / "flow_notes.txt") << "not a step";
  io::write_tet_mesh_vtu((dir / "flow_x.vtu").string(), box(9.0));  // not a number: not a step
  const std::string pattern = (dir / "flow_*.vtu").string();
  const CliRun info = run("info '" + pattern + "'");
  ASSERT_EQ(info.code, 0) << info.err;
  for (const std::string& line : std::vector<std::string>{"(time series, 3 steps;", "step 0: t = 0, " + (dir / "flow_9.vtu").string(),
                                 "step 1: t = 1, " + (dir / "flow_10.vtu").string(), "step 2: t = 2, " + (dir / "flow_100.vtu").string()})
    EXPECT_NE(info.out.find(line), std::string::npos) << line << " in\n" << info.out;
  const std::vector<double> expected = {0.5, 1.0, 2.0};  // in number order
  for (size_t i = 0; i < expected.size(); ++i) {
    const fs::path pfm = dir / ("s" + std::to_string(i) + ".pfm");
    const CliRun r = run("render '" + pattern + "' --time-step " + std::to_string(i) + kView + " --output " + pfm.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const io::FloatImage img = io::read_pfm(pfm.string());
    EXPECT_NEAR(img.pixels[(kSide / 2) * kSide + kSide / 2], 2.0 * expected[i], 1e-5 * 2.0 * expected[i]) << "step " << i;
  }
  const fs::path png = dir / "o.png";
  const auto refused = [&](const std::string& path, const std::string& says) {
    const CliRun r = run("render '" + path + "' --size 8x8 --output " + png.string());
    EXPECT_EQ(r.code, 2) << path << ": " << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << path << ": " << r.err;
  };
  refused((dir / "nothing_*.vtu").string(), "no file of its folder matches");
  refused((dir / "flow_*_*.vtu").string(), "one * in its file name");
  refused((dir / "flow_*.stl").string(), "are mesh files");
  refused((dir / "missing" / "flow_*.vtu").string(), "does not exist");
  io::write_tet_mesh_vtu((dir / "flow_09.vtu").string(), box(1.0));
  refused(pattern, "flow_09.vtu and flow_9.vtu are both step number 9");
}

// The bench's time sweep: a row per step and quantity, each measured against that step's own
// reference (its error as small as any GPU row's: the boxes' constant extinction is exact).
TEST(CliTimeSeries, TheBenchTimesEveryStep) {
  const fs::path dir = work_dir() / "bench_series";
  const fs::path pvd = write_series(dir);
  const fs::path out = dir / "bench";
  const CliRun r = run("bench " + pvd.string() + " --quick --sweeps time --no-plots --no-peers --array extinction --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  // Each step's transmittance and colour (the extinction array is the colour's scalar too), then
  // the step switches.
  test::expect_time_sweep_rows(out / "bench.csv", kSigma.size());
  const CliRun bad = run("bench " + (dir / "steps" / "nothing.pvd").string() + " --quick --sweeps time --out " + (dir / "b2").string());
  EXPECT_EQ(bad.code, 2) << bad.err;
  EXPECT_NE(bad.err.find("nothing.pvd: file does not exist"), std::string::npos) << bad.err;
}

// One tetrahedron as VTK XML (ASCII), with one point array of that name.
void write_tet_with_array(const fs::path& path, const std::string& array) {
  std::ofstream(path) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n<UnstructuredGrid>\n"
                         "<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
                         "<PointData><DataArray type=\"Float64\" Name=\"" << array << "\" format=\"ascii\">0 1 2 3</DataArray></PointData>\n"
                         "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">0 0 0 1 0 0 0 1 0 0 0 1</DataArray></Points>\n"
                         "<Cells><DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">0 1 2 3</DataArray>\n"
                         "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4</DataArray>\n"
                         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10</DataArray></Cells>\n"
                         "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

// Steps whose arrays differ: colour by a chosen array would colour step 1 by another quantity
// than step 0, so it is refused naming both; named with --array, a step without it is refused by
// the reader, naming the step's file; steps with the same array draw.
TEST(CliTimeSeries, StepsWhoseColourArraysDifferAreRefused) {
  const fs::path dir = work_dir() / "arrays";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_tet_with_array(dir / "s_0.vtu", "pressure");
  write_tet_with_array(dir / "s_1.vtu", "temperature");
  write_tet_with_array(dir / "t_0.vtu", "pressure");
  write_tet_with_array(dir / "t_1.vtu", "pressure");
  const fs::path png = dir / "o.png";
  const std::string view = " --quantity color --size 8x8 --eye 2,2,2 --target 0,0,0 --output " + png.string();
  CliRun r = run("render '" + (dir / "s_*.vtu").string() + "' --time-step 1" + view);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("step 1 would be coloured by 'temperature' and step 0 by 'pressure': the steps' arrays differ"), std::string::npos)
      << r.err;
  r = run("render '" + (dir / "s_*.vtu").string() + "' --time-step 1 --array pressure" + view);
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("s_1.vtu: has no array 'pressure'"), std::string::npos) << r.err;
  r = run("render '" + (dir / "s_*.vtu").string() + "' --time-step 0" + view);  // step 0 itself draws
  EXPECT_EQ(r.code, 0) << r.err;
  r = run("render '" + (dir / "t_*.vtu").string() + "' --time-step 1" + view);
  EXPECT_EQ(r.code, 0) << r.err;
}

}  // namespace
}  // namespace prismoid
