// End-to-end: the prismoid executable as a user runs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app/bench/bench_table.hpp"
#include "app/common/grid_dataset.hpp"
#include "app/common/volume_option_table.hpp"
#include "io/image_io.hpp"
#include "io/surface_io.hpp"
#include "io/vdb_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/reference/emission_absorption.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/volume/region_mesh.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/generators.hpp"
#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::slurp;
using test::cli::run;
using test::cli::work_dir;

// The command is refused as bad input (exit code 2) with a message that contains `says`.
void expect_refused(const std::string& command, const std::string& says) {
  const CliRun r = run(command);
  EXPECT_EQ(r.code, 2) << command;
  EXPECT_NE(r.err.find(says), std::string::npos) << command << ": " << r.err;
}

// An aggregate check of a whole image written by the CLI against the CPU reference: RMSE
// below 1e-3 of the peak. The per-pixel tolerances (sub-pixel snapping, float32) are derived
// and checked in tests/volume; here we only prove the CLI path delivers that image.
void expect_close_to_reference(const io::FloatImage& img, const std::vector<double>& ref) {
  ASSERT_EQ(img.pixels.size(), ref.size());
  double peak = 0.0, rms = 0.0;
  for (size_t i = 0; i < ref.size(); ++i) {
    peak = std::max(peak, ref[i]);
    const double d = double(img.pixels[i]) - ref[i];
    rms += d * d;
  }
  rms = std::sqrt(rms / double(ref.size()));
  EXPECT_GT(peak, 0.5);
  EXPECT_LT(rms, 1e-3 * peak);
}

TEST(Cli, DevicesListsAMeshShaderDevice) {
  const CliRun r = run("devices --validate");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("mesh shader: yes"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ray query:"), std::string::npos);
  EXPECT_NE(r.out.find("default choice: device"), std::string::npos);
}

TEST(Cli, EveryVerbHasHelp) {
  for (const char* verb : {"render", "view", "devices", "convert", "info", "bench"}) {
    const CliRun r = run(std::string(verb) + " --help");
    EXPECT_EQ(r.code, 0) << verb;
    EXPECT_NE(r.out.find("usage: prismoid " + std::string(verb)), std::string::npos) << r.out;
  }
  EXPECT_EQ(run("--help").code, 0);
}

// The volume mode table is what the command line knows: render's help lists each mode with its
// summary, an unknown mode is refused naming every one, `devices` lists the GPU modes it draws.
TEST(Cli, VolumeModesComeFromTheirTable) {
  const CliRun help = run("render --help");
  ASSERT_EQ(help.code, 0) << help.err;
  // The help wraps the summaries: compare with white space folded.
  const auto folded = [](const std::string& text) {
    std::string out;
    std::istringstream words(text);
    for (std::string w; words >> w;) out += (out.empty() ? "" : " ") + w;
    return out;
  };
  const std::string help_text = folded(help.out);
  std::string names;
  for (const frame::VolumeMode& m : frame::volume_mode_table()) {
    EXPECT_NE(help_text.find(" " + std::string(m.name) + " " + folded(std::string(m.summary))), std::string::npos)
        << m.name << " and its summary missing from:\n" << help.out;
    names += (names.empty() ? "" : ", ") + std::string(m.name);
  }
  EXPECT_NE(help.out.find("(default: interval; interval-sorted for --quantity color)"), std::string::npos) << help.out;
  const CliRun bad = run("render --output x.png --mode interval-upside-down");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("unknown mode 'interval-upside-down' (available: " + names + ")"), std::string::npos) << bad.err;
  const CliRun devices = run("devices");
  ASSERT_EQ(devices.code, 0) << devices.err;
  EXPECT_NE(devices.out.find("volume modes it draws: interval, interval-sorted, interval-exact-order, interval-march, "
                             "interval-march-exact-order\n"),
            std::string::npos)
      << devices.out;
}

// The volume option table is what the command line knows: render's help lists each option with
// its value's form and help, view's names each one, and render, view and info take every one
// (an option missing from a verb's parse would be refused as unknown, exit 2, before any work).
TEST(Cli, VolumeOptionsComeFromTheirTable) {
  const CliRun help = run("render --help");
  ASSERT_EQ(help.code, 0) << help.err;
  const CliRun view = run("view --help");
  ASSERT_EQ(view.code, 0) << view.err;
  for (const app::VolumeOption& o : app::volume_option_table()) {
    const std::string flag = "--" + std::string(o.name);
    EXPECT_NE(view.out.find(flag), std::string::npos) << flag << " missing from view's help:\n" << view.out;
    if (o.group == app::VolumeOptionGroup::Mode) continue;  // listed from the mode and backend tables
    const std::string line = "  " + flag + (o.flag() ? "" : " " + std::string(o.value)) + "  ";
    const size_t at = help.out.find(line);
    ASSERT_NE(at, std::string::npos) << line << " missing from:\n" << help.out;
    const std::string text(o.help);
    EXPECT_NE(help.out.find(text.substr(0, text.find(' ', 16)), at), std::string::npos) << flag << "'s help";
  }
  // Every verb parses every option: a bad value is refused by name (exit 2), never as an unknown option.
  for (const char* verb : {"render", "view", "info"})
    for (const app::VolumeOption& o : app::volume_option_table()) {
      const std::string flag = "--" + std::string(o.name);
      const CliRun r = run(std::string(verb) + " no-such-file.vtu " + flag + (o.flag() ? "" : " x") +
                           (std::string(verb) == "render" ? " --output o.png" : ""));
      EXPECT_EQ(r.err.find("unknown option"), std::string::npos) << verb << " " << flag << ": " << r.err;
      EXPECT_NE(r.code, 0) << verb << " " << flag;
    }
  // The bench sweeps values the option takes.
  for (const std::string& t : app::volume_option_sweep("tetlet-size", false))
    EXPECT_NE(std::find(volume::kTetletSizes.begin(), volume::kTetletSizes.end(), std::stoul(t)), volume::kTetletSizes.end()) << t;
  EXPECT_EQ(app::volume_option_sweep("tetlet-size", true).size(), 1u);
  EXPECT_TRUE(app::volume_option_sweep("array", false).empty());
}

// --volume-backend offers the volume backend table: the help lists each backend with its summary,
// an unknown name is refused naming every one, `devices` says which GPU backends a device runs,
// and the CPU reference is a backend too (the reference mode's frame; refused with a GPU mode).
TEST(Cli, VolumeBackendsComeFromTheirTable) {
  const CliRun help = run("render --help");
  ASSERT_EQ(help.code, 0) << help.err;
  std::string names, gpu_names;
  for (const volume::VolumeBackendInfo* b : volume::volume_backend_table()) {
    const std::string summary(b->summary);
    EXPECT_NE(help.out.find(std::string(b->name) + "  "), std::string::npos) << b->name << " missing from:\n" << help.out;
    EXPECT_NE(help.out.find(summary.substr(0, summary.find(' ', 20))), std::string::npos) << b->name << "'s summary missing";
    names += std::string(b->name) + ", ";
    if (b->gpu()) gpu_names += (gpu_names.empty() ? "" : ", ") + std::string(b->name);
  }
  const CliRun bad = run("render ball --size 8x8 --output x.png --volume-backend quantum");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("unknown backend 'quantum' (available: " + names + "auto)"), std::string::npos) << bad.err;
  const CliRun devices = run("devices");
  ASSERT_EQ(devices.code, 0) << devices.err;
  EXPECT_NE(devices.out.find("volume backends: " + gpu_names + "\n"), std::string::npos) << devices.out;

  const fs::path cpu = work_dir() / "backend_cpu.pfm", reference = work_dir() / "mode_reference.pfm";
  CliRun r = run("render ball --quantity optical-depth --size 24x16 --volume-backend cpu --output " + cpu.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("CPU reference (double precision)"), std::string::npos) << r.out;
  r = run("render ball --quantity optical-depth --size 24x16 --mode reference --output " + reference.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(io::read_pfm(cpu.string()).pixels, io::read_pfm(reference.string()).pixels);
  r = run("render ball --size 8x8 --volume-backend cpu --mode interval --output " + cpu.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--volume-backend cpu: draws the CPU reference: --mode interval is drawn on the GPU"), std::string::npos) << r.err;
  r = run("view ball --volume-backend cpu");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--volume-backend cpu: runs on the CPU: use `prismoid render --volume-backend cpu`"), std::string::npos) << r.err;
}

TEST(Cli, RenderWritesPfmThatMatchesTheReference) {
  const fs::path pfm = work_dir() / "depth.pfm";
  const fs::path stats = work_dir() / "stats.json";
  const CliRun r = run("render --validate --quantity optical-depth --size 40x30 --eye 2,1.5,4.5 --target 0,0,0 --output " +
                    pfm.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("interval-shading"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string());
  ASSERT_EQ(img.width, 40u);
  ASSERT_EQ(img.height, 30u);

  Camera c;
  c.eye = {2, 1.5, 4.5};
  c.target = {0, 0, 0};
  c.fovy_degrees = 40.0;
  const TetMesh mesh = make_default_volume();
  c.near_distance = fit_camera(bounds_of(mesh)).near_distance;
  const auto ref = reference::optical_depth_image(mesh, c, 40, 30);
  expect_close_to_reference(img, ref);

  const std::string js = slurp(stats);
  EXPECT_NE(js.find("\"name\": \"interval-shading\""), std::string::npos) << js;
  EXPECT_NE(js.find("\"validation_messages\": 0"), std::string::npos) << js;
}

TEST(Cli, ReferenceModeWritesTheCpuReference) {
  const fs::path pfm = work_dir() / "ref.pfm";
  const CliRun r = run("render --mode reference --quantity transmittance --size 20x15 --eye 2,1.5,4.5 --target 0,0,0 --output " +
                       pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("CPU reference"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string());
  Camera c;
  c.eye = {2, 1.5, 4.5};
  c.target = {0, 0, 0};
  const TetMesh mesh = make_default_volume();
  c.near_distance = fit_camera(bounds_of(mesh)).near_distance;
  const auto tau = reference::optical_depth_image(mesh, c, 20, 15);
  ASSERT_EQ(img.pixels.size(), tau.size());
  for (size_t i = 0; i < tau.size(); ++i)
    EXPECT_NEAR(img.pixels[i], std::exp(-tau[i]), 1e-7) << i;  // float32 rounding of a value <= 1
}

TEST(Cli, RendersAVtuFileLikeTheSameMeshBuiltIn) {
  // The default dataset written as .vtu and read back through VTK renders bit-identically.
  const fs::path vtu = work_dir() / "default.vtu";
  io::write_tet_mesh_vtu(vtu.string(), make_default_volume());
  const fs::path from_file = work_dir() / "file.pfm", built_in = work_dir() / "builtin.pfm";
  const std::string camera = " --quantity optical-depth --size 32x24 --eye 2,1.5,4.5 --target 0,0,0 --near 0.1 --output ";
  CliRun r = run("render " + vtu.string() + " --array extinction" + camera + from_file.string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("render" + camera + built_in.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const auto a = io::read_pfm(from_file.string()), b = io::read_pfm(built_in.string());
  EXPECT_EQ(a.pixels, b.pixels);
  double sum = 0.0;
  for (float v : a.pixels) sum += double(v);
  EXPECT_GT(sum, 1.0);
}

TEST(Cli, PointArrayRendersTheLinearFieldLikeTheReference) {
  TetMesh mesh = make_default_volume();
  const fs::path vtu = work_dir() / "points.vtu", pfm = work_dir() / "points.pfm";
  const CliRun converted = run("convert " + vtu.string());
  ASSERT_EQ(converted.code, 0) << converted.err;
  const CliRun r = run("render " + vtu.string() + " --array scalars --quantity optical-depth --size 32x24 --eye 2,1.5,4.5 "
                       "--target 0,0,0 --near 0.1 --output " + pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  mesh.point_extinction = mesh.point_scalars;
  Camera c;
  c.eye = {2, 1.5, 4.5};
  c.target = {0, 0, 0};
  c.near_distance = 0.1;
  const auto ref = reference::optical_depth_image(mesh, c, 32, 24);
  const auto img = io::read_pfm(pfm.string());
  expect_close_to_reference(img, ref);
}

// Colour of a file with one point array (and Prismoid's "extinction" cell array) needs no
// --array: the field is picked as ParaView picks it, said on stderr, and the image is the one
// naming the array gives.
TEST(Cli, ColourOfAFileWithOneArrayNeedsNoFlags) {
  const fs::path vtu = work_dir() / "one_array.vtu", picked = work_dir() / "picked.pfm", named = work_dir() / "named.pfm";
  const CliRun converted = run("convert " + vtu.string());
  ASSERT_EQ(converted.code, 0) << converted.err;
  const std::string common = " --quantity color --mode interval-exact-order --size 32x24 --eye 2,1.5,4.5 --target 0,0,0 --output ";
  const CliRun a = run("render " + vtu.string() + common + picked.string());
  ASSERT_EQ(a.code, 0) << a.err;
  EXPECT_NE(a.err.find("the scalar field is the only point array, 'scalars' (--array NAME picks another)"), std::string::npos) << a.err;
  const CliRun b = run("render " + vtu.string() + " --array scalars" + common + named.string());
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_EQ(b.err.find("the scalar field is"), std::string::npos) << "a named array needs no note";
  EXPECT_EQ(io::read_pfm(picked.string()).pixels, io::read_pfm(named.string()).pixels);
}

// An OpenVDB fog volume made by `convert` from the ball's surface, rendered: the image is the
// reference's optical depth through the same voxel tetrahedra (read here by io, as the CLI does).
TEST(Cli, VdbFogVolumeFromASurfaceRendersLikeTheReference) {
  const fs::path vdb = work_dir() / "ball_fog.vdb", pfm = work_dir() / "ball_fog.pfm", vtu = work_dir() / "ball_fog.vtu";
  const CliRun made = run("convert ball:2 " + vdb.string() + " --voxel-size 0.2");
  ASSERT_EQ(made.code, 0) << made.err;
  EXPECT_NE(made.out.find("fog volume 'density', voxel size 0.2"), std::string::npos) << made.out;
  EXPECT_FALSE(fs::exists(vdb.string() + ".partial"));
  const CliRun r = run("render " + vdb.string() + " --quantity optical-depth --size 24x24 --eye 0.5,1,4 --target 0,0,0 --near 0.1 "
                       "--output " + pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const TetMesh mesh = io::read_vdb_voxels(vdb.string());
  Camera c;
  c.eye = {0.5, 1, 4};
  c.target = {0, 0, 0};
  c.near_distance = 0.1;
  expect_close_to_reference(io::read_pfm(pfm.string()), reference::optical_depth_image(mesh, c, 24, 24));

  const CliRun info = run("info " + vdb.string());
  ASSERT_EQ(info.code, 0) << info.err;
  EXPECT_NE(info.out.find("grid 'density': float, fog volume"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("as tetrahedra: " + std::to_string(mesh.tets.size()) + " "), std::string::npos) << info.out;
  const CliRun converted = run("convert " + vdb.string() + " " + vtu.string());
  ASSERT_EQ(converted.code, 0) << converted.err;
  EXPECT_EQ(io::read_tet_mesh(vtu.string()).tets.size(), mesh.tets.size());
}

// The march modes take a .vdb grid as a field over its active regions (not its voxel
// tetrahedra), and --mode reference marches the same trilinear field on the CPU. Both are
// midpoint sums of sigma = max(f, 0), which is G-Lipschitz along a line (G = the grid's gradient
// bound), so each step of length h is within G h^2 / 4 of the integral: along a chord of length
// L <= D (the regions' diagonal) the GPU (h = D / 100) and the reference (h = D / 2000) are within
// G D (D / 100 + D / 2000) / 4 of each other, plus float rounding (1e-4 of the depth here).
TEST(Cli, VdbMarchesItsActiveRegionsLikeTheReference) {
  const fs::path vdb = work_dir() / "march_fog.vdb", march = work_dir() / "vdb_march.pfm", ref = work_dir() / "vdb_ref.pfm";
  const fs::path stats = work_dir() / "vdb_march.json";
  ASSERT_EQ(run("convert ball:2 " + vdb.string() + " --voxel-size 0.2").code, 0);
  const std::string args = "render " + vdb.string() + " --quantity optical-depth --size 24x24 --eye 0.5,1,4 --target 0,0,0 --output ";
  CliRun r = run(args + march.string() + " --mode interval-march --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run(args + ref.string() + " --mode reference");
  ASSERT_EQ(r.code, 0) << r.err;

  const auto grid = app::grid_from_vdb(vdb.string(), {});
  const TetMesh regions = app::grid_dataset_mesh(*grid, 1.0);
  const TetMesh voxels = io::read_vdb_voxels(vdb.string());
  EXPECT_LT(regions.tets.size(), voxels.tets.size() / 4);  // leaf boxes, not voxels
  EXPECT_NE(slurp(stats.string()).find("\"cells\": " + std::to_string(regions.tets.size()) + ","), std::string::npos);
  // The marched grid is the file's grid: at every voxel centre (the voxel mesh's points, read by
  // the independent voxel path) its trilinear field is the voxel's value.
  ASSERT_EQ(voxels.point_extinction.size(), voxels.points.size());
  for (size_t i = 0; i < voxels.points.size(); ++i)
    ASSERT_NEAR(volume::evaluate(*grid, voxels.points[i]), voxels.point_extinction[i], 1e-6) << "voxel centre " << i;

  const Bounds b = bounds_of(regions);
  const double D = glm::length(b.max - b.min), G = volume::gradient_bound(*grid);
  const double tol = G * D * (D / 100.0 + D / 2000.0) / 4.0;
  const auto a = io::read_pfm(march.string()), c = io::read_pfm(ref.string());
  ASSERT_EQ(a.pixels.size(), c.pixels.size());
  size_t covered = 0;
  double peak = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    ASSERT_TRUE(std::isfinite(a.pixels[i]) && std::isfinite(c.pixels[i])) << i;
    EXPECT_NEAR(a.pixels[i], c.pixels[i], tol + 1e-4 * (1.0 + double(c.pixels[i]))) << "pixel " << i;
    covered += c.pixels[i] > 0.1f;
    peak = std::max(peak, double(c.pixels[i]));
  }
  EXPECT_GT(covered, 100u);
  EXPECT_GT(peak, 5.0 * tol);  // the bound is tight enough to mean something
}

TEST(Cli, BadVdbInputExitsWithTwoAndLeavesNoFile) {
  const std::string d = work_dir().string() + "/";
  std::ofstream(d + "garbage.vdb") << "not an OpenVDB file, only some words";
  const CliRun made = run("convert ball:1 " + d + "small.vdb --vdb levelset --voxel-size 0.25");
  ASSERT_EQ(made.code, 0) << made.err;
  std::string bytes = slurp(d + "small.vdb");
  std::ofstream(d + "cut.vdb", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::ofstream(d + "open.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  struct Case { std::string args, fragment; };
  const std::vector<Case> cases = {
      {"info " + d + "garbage.vdb", "garbage.vdb: is not a readable VDB file"},
      {"render --output x.png " + d + "cut.vdb", "cut.vdb: is not a readable VDB file"},
      {"render --output x.png " + d + "small.vdb --grid smoke", "small.vdb: has no grid 'smoke' (grids: 'surface' (float))"},
      {"render --output x.png " + d + "small.vdb --array a", "--array"},
      {"render --output x.png ball --grid a", "--grid: applies to OpenVDB files"},
      {"convert ball:1 " + d + "x.vdb --vdb smoke", "--vdb: is fog or levelset"},
      {"convert ball:1 " + d + "x.vdb --voxel-size 0", "--voxel-size: must be positive"},
      {"convert ball:1 " + d + "x.vdb --voxel-size 0.00001", "voxels in the bounding box"},
      {"convert " + d + "open.off " + d + "x.vdb", "open.off: the surface is not closed"},
      {"convert ball:1 /no/such/dir/x.vdb", "/no/such/dir/x.vdb: the folder '/no/such/dir' does not exist"},
      {"convert ball:1 " + d + "x.vtu --vdb fog", "--vdb: applies to .vdb output only"},
  };
  for (const auto& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.fragment), std::string::npos) << c.args << "\n" << r.err;
  }
  EXPECT_FALSE(fs::exists(d + "x.vdb"));
  EXPECT_FALSE(fs::exists(d + "x.vdb.partial"));
}

// grid:NAME[:N] marches the sampled field; the reference renders the same trilinear field. Both
// cover the region (blocks where Marschner-Lobb, in [0, 1], is above 1/1000: all of [-1,1]^3)
// with finite values; the GPU test suite compares the march with the CPU pixel by pixel.
TEST(Cli, GridDatasetMarchesAndHasAReference) {
  const fs::path march = work_dir() / "grid_march.pfm", ref = work_dir() / "grid_ref.pfm";
  const std::string args = "render grid:marschner-lobb:17 --quantity optical-depth --size 24x24 --eye 0.5,0.8,4 --target 0,0,0 --output ";
  CliRun r = run(args + march.string() + " --mode interval-march");
  ASSERT_EQ(r.code, 0) << r.err;
  r = run(args + ref.string() + " --mode reference");
  ASSERT_EQ(r.code, 0) << r.err;
  const auto a = io::read_pfm(march.string()), b = io::read_pfm(ref.string());
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  size_t both = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    EXPECT_TRUE(std::isfinite(a.pixels[i]) && std::isfinite(b.pixels[i])) << i;
    both += a.pixels[i] > 0.0f && b.pixels[i] > 0.0f;
  }
  EXPECT_GT(both, 200u);
}

TEST(Cli, DensityScaleMultipliesTheOpticalDepth) {
  const fs::path one = work_dir() / "one.pfm", two = work_dir() / "two.pfm";
  const std::string args = "render --quantity optical-depth --size 24x16 --output ";
  ASSERT_EQ(run(args + one.string()).code, 0);
  ASSERT_EQ(run(args + two.string() + " --density-scale 2").code, 0);
  const auto a = io::read_pfm(one.string()), b = io::read_pfm(two.string());
  double peak = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    peak = std::max(peak, double(a.pixels[i]));
    // Doubling every sigma doubles each float term exactly: the sums agree to rounding.
    EXPECT_NEAR(b.pixels[i], 2.0f * a.pixels[i], 1e-5f * (1.0f + a.pixels[i])) << i;
  }
  EXPECT_GT(peak, 0.5);
}

TEST(Cli, RenderWritesPng) {
  const fs::path png = work_dir() / "default.png";
  const CliRun r = run("render --size 64x48 --output " + png.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_GT(fs::file_size(png), 100u);
  EXPECT_NE(r.out.find("wrote " + png.string()), std::string::npos);
}

// Colour: emission-absorption of the default dataset's density through a transfer function,
// composited in exact order on the GPU, against the CPU reference over the same background.
TEST(Cli, ColorInExactOrderMatchesTheReference) {
  const fs::path pfm = work_dir() / "color.pfm";
  const fs::path stats = work_dir() / "color.json";
  const CliRun r = run("render --validate --quantity color --mode interval-exact-order --tf viridis --density-scale 10 "
                       "--background 0,0,0 --size 40x30 --eye 2,1.5,4.5 --target 0,0,0 --output " + pfm.string() +
                       " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const io::FloatImage img = io::read_pfm(pfm.string());
  ASSERT_EQ(img.channels, 3u);
  Camera c;
  c.eye = {2, 1.5, 4.5};
  c.target = {0, 0, 0};
  const TetMesh mesh = make_default_volume();
  c.near_distance = fit_camera(bounds_of(mesh)).near_distance;
  volume::TransferFunction tf = volume::preset("viridis");
  const auto [lo, hi] = std::minmax_element(mesh.point_scalars.begin(), mesh.point_scalars.end());
  tf.range_lo = *lo;
  tf.range_hi = *hi;
  tf.density_scale = 10.0;
  const auto ref = reference::emission_absorption_image(mesh, tf, c, 40, 30);
  // Black background: the PFM holds the premultiplied colour. Aggregate check, as above.
  ASSERT_EQ(img.pixels.size(), 3 * ref.pixels.size());
  double peak = 0.0, rms = 0.0;
  for (size_t i = 0; i < ref.pixels.size(); ++i)
    for (int channel = 0; channel < 3; ++channel) {
      peak = std::max(peak, ref.pixels[i][channel]);
      const double d = double(img.pixels[3 * i + size_t(channel)]) - ref.pixels[i][channel];
      rms += d * d;
    }
  rms = std::sqrt(rms / double(img.pixels.size()));
  EXPECT_GT(peak, 0.1);
  EXPECT_LT(rms, 1e-3 * peak);
  const std::string js = slurp(stats);
  EXPECT_NE(js.find("\"ordering\": \"exact"), std::string::npos) << js;
  EXPECT_NE(js.find("\"order_exact\": true"), std::string::npos) << js;
  EXPECT_NE(js.find("\"quantity\": \"color\""), std::string::npos) << js;
  EXPECT_EQ(js.find("\"name\": \"sort\""), std::string::npos) << js;  // the exact order is made on the CPU
}

// The first image a new user gets (`render` of the embedded dataset, no options): colour of its
// smooth point field in exact order, through the default look (viridis, opacity rising from the
// field's median but at least 0.2 of its range, extinction 35 over the bounds' diagonal, an
// almost black background), computed here from those rules independently; and, with
// --reference-error, how far it is from the CPU reference, which is this test's reference too.
TEST(Cli, TheFirstImageIsExactOrderColourWithItsErrorPrinted) {
  const fs::path pfm = work_dir() / "first.pfm", stats = work_dir() / "first.json";
  const CliRun r = run("render --validate --reference-error --size 40x30 --eye 2,1.5,4.5 --target 0,0,0 --output " + pfm.string() +
                       " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("against the CPU reference (double precision, exact per-pixel order"), std::string::npos) << r.out;
  const std::string js = slurp(stats);
  EXPECT_NE(js.find("\"quantity\": \"color\""), std::string::npos) << js;
  EXPECT_NE(js.find("\"mode\": \"interval-exact-order\""), std::string::npos) << js;
  EXPECT_NE(js.find("\"order_exact\": true"), std::string::npos) << js;
  EXPECT_NE(js.find("\"transfer_function\": \"viridis, opacity from the field's median\""), std::string::npos) << js;
  const nlohmann::json parsed = nlohmann::json::parse(js);
  ASSERT_TRUE(parsed.contains("reference_error")) << js;
  const double printed_rmse = parsed["reference_error"]["rmse"].get<double>();
  EXPECT_EQ(parsed["reference_error"]["non_finite"].get<size_t>(), 0u);

  const TetMesh mesh = make_default_volume();
  Camera c;
  c.eye = {2, 1.5, 4.5};
  c.target = {0, 0, 0};
  c.near_distance = fit_camera(bounds_of(mesh)).near_distance;
  volume::TransferFunction tf = volume::preset("viridis");
  std::vector<double> values = mesh.point_scalars;
  std::sort(values.begin(), values.end());
  tf.range_lo = values.front();
  tf.range_hi = values.back();
  const double median = values[values.size() / 2];
  const double from = std::clamp((median - tf.range_lo) / (tf.range_hi - tf.range_lo), 0.2, 0.8);
  tf.opacity = {{0.0, 0.0}, {from, 0.0}, {1.0, 1.0}};
  const Bounds b = bounds_of(mesh);
  tf.density_scale = 35.0 / glm::length(b.max - b.min);
  const auto ref = reference::emission_absorption_image(mesh, tf, c, 40, 30);
  const glm::dvec3 background(0.01f, 0.01f, 0.015f);
  const io::FloatImage img = io::read_pfm(pfm.string());
  ASSERT_EQ(img.pixels.size(), 3 * ref.pixels.size());
  double rms = 0.0, peak = 0.0;
  for (size_t i = 0; i < ref.pixels.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const double shown = ref.pixels[i][k] + (1.0 - ref.pixels[i].a) * background[k];
      peak = std::max(peak, shown);
      const double d = double(img.pixels[3 * i + size_t(k)]) - shown;
      rms += d * d;
    }
  rms = std::sqrt(rms / double(img.pixels.size()));
  EXPECT_GT(peak, 0.1);       // the structure is there, not a faint haze
  EXPECT_LT(rms, 1e-3 * peak);
  // The printed error is this image's against this reference (float32 rounding of the reference
  // display aside: 1e-7 per value).
  EXPECT_NEAR(printed_rmse, rms, 1e-6 + 1e-3 * rms);
  expect_refused("render --mode reference --reference-error --size 8x8 --output " + (work_dir() / "r.pfm").string(),
                 "is the reference itself");
}

// Colour's default extinction follows the data's size, so the same data in other units (here
// millimetres for metres) looks the same: neither vanishing when large nor saturating when small.
TEST(Cli, ColourLooksTheSameWhateverTheDataUnits) {
  TetMesh metres = make_default_volume();
  TetMesh millimetres = metres;
  for (glm::dvec3& p : millimetres.points) p *= 1000.0;
  const fs::path a = work_dir() / "metres.vtu", b = work_dir() / "millimetres.vtu";
  io::write_tet_mesh_vtu(a.string(), metres);
  io::write_tet_mesh_vtu(b.string(), millimetres);
  const std::string common = " --quantity color --mode interval-exact-order --size 32x24 --output ";
  const fs::path pa = work_dir() / "metres.pfm", pb = work_dir() / "millimetres.pfm";
  ASSERT_EQ(run("render " + a.string() + common + pa.string()).code, 0);
  ASSERT_EQ(run("render " + b.string() + common + pb.string()).code, 0);
  const io::FloatImage ia = io::read_pfm(pa.string()), ib = io::read_pfm(pb.string());
  ASSERT_EQ(ia.pixels.size(), ib.pixels.size());
  double peak = 0.0, largest = 0.0;
  for (size_t i = 0; i < ia.pixels.size(); ++i) {
    peak = std::max(peak, double(ia.pixels[i]));
    largest = std::max(largest, std::abs(double(ia.pixels[i]) - double(ib.pixels[i])));
  }
  EXPECT_GT(peak, 0.1);
  EXPECT_LT(largest, 1e-4);  // float32 geometry at either scale; a fixed density would differ by 1000x in optical depth
}

TEST(Cli, SortedColorRunsTheSortPassAndSaysSo) {
  const fs::path stats = work_dir() / "sorted.json";
  const CliRun r = run("render --quantity color --size 24x18 --output " + (work_dir() / "sorted.png").string() + " --stats " +
                       stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string js = slurp(stats);
  EXPECT_NE(js.find("\"mode\": \"interval-sorted\""), std::string::npos) << js;  // colour's default mode
  EXPECT_NE(js.find("\"name\": \"sort\""), std::string::npos) << js;
  EXPECT_NE(js.find("\"order_exact\": false"), std::string::npos) << js;
  // Order-independent quantities never sort, whatever the mode.
  const CliRun od = run("render --quantity optical-depth --mode interval-sorted --size 24x18 --output " +
                        (work_dir() / "od.png").string() + " --stats " + stats.string());
  ASSERT_EQ(od.code, 0) << od.err;
  EXPECT_EQ(slurp(stats).find("\"name\": \"sort\""), std::string::npos);
}

// The frame plan without a GPU: an order-independent quantity plans no sort (the skipped list
// says why), colour in sorted mode plans one; render's stats carry the same plan.
using bench::csv_fields;  // the bench CSV's own reader of one line

TEST(Cli, QuickBenchMeasuresEveryConfigurationAgainstTheReference) {
  const fs::path dir = work_dir() / "bench";
  // 128x96 rather than the preset's 96x72: the optical-depth bound below is an aggregate
  // (RMSE < 1e-3 of the peak) dominated by silhouette pixels, whose share falls as the image
  // grows; at 96x72 the default dataset sits at 0.96e-3, at 128x96 at 0.71e-3.
  const CliRun r = run("bench --quick --size 128x96 --validate --out " + dir.string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::ifstream csv(dir / "bench.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  const std::vector<std::string> header = csv_fields(line);
  const auto column = [&](const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return size_t(it - header.begin());
  };
  const size_t dataset = column("dataset"), quantity = column("quantity"), mode = column("mode"),
               settings = column("settings"), rmse = column("rmse"), max_abs = column("max_abs"), peak = column("peak"),
               non_finite = column("non_finite"), ssim = column("ssim"), sweep = column("sweep"), cells = column("cells"),
               timer = column("timer"), flip = column("flip_mean");
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) rows.push_back(csv_fields(line));
  // The default dataset in 7 quick configurations; ball:2 has no scalar array, so only its 3
  // order-independent ones (optical depth twice, transmittance); the march-step sweep's field
  // with its tetrahedra and two steps, optical depth and colour each (6); the cell-count sweep's
  // two meshes, optical depth and colour each (4); VTK's three mappers beside the default
  // dataset's colour and the ball's transmittance (6); the Cornell box in each surface mode
  // this device draws (forward, htex, texel, msa and fastatlas with shadows off and on; htex-gi,
  // htex-gi-unbiased and htex-pt with shadows: 13); and the compute backend beside the mesh-shader
  // one: the default dataset's optical depth, transmittance and colour (3), the ball's optical
  // depth and transmittance (2), the cell-count sweep's two meshes in optical depth and colour (4);
  // the default dataset cut by a square in each surface mode without indirect light (forward,
  // htex, texel, msa, fastatlas) on each volume backend (10).
  ASSERT_EQ(rows.size(), 58u) << slurp(dir / "bench.csv");
  std::map<std::string, double> flip_of;  // the default dataset's colour, by mode/settings
  std::multiset<std::string> peers;        // quantity/mode of the wall-clock rows
  std::map<std::string, double> default_rmse, default_ssim;  // by quantity/mode/settings
  std::map<std::string, double> march_rmse;                  // by quantity/settings
  std::set<std::string> sweeps, cell_counts;
  std::map<std::string, double> mixed_rmse;  // by surface mode/backend
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), header.size());
    sweeps.insert(row[sweep]);
    EXPECT_TRUE(std::isfinite(std::stod(row[rmse])) && std::isfinite(std::stod(row[max_abs]))) << row[dataset];
    const double s = std::stod(row[ssim]);  // similarity: at most 1 (identical)
    EXPECT_TRUE(s > 0.5 && s <= 1.0 + 1e-12) << row[dataset] << " " << row[mode] << " ssim " << s;
    EXPECT_EQ(row[non_finite], "0");
    const bool field = row[dataset].rfind("field:", 0) == 0;
    if (!field) {  // close images (the field's tetrahedra are not; GI rows carry Monte Carlo noise, which
                   // surfaces' display RGB, peak 1, shows: one path per texel gives 0.83)
      EXPECT_GT(s, row[mode].rfind("htex-", 0) == 0 ? 0.75 : 0.9) << row[dataset] << " " << row[mode];
    }
    if (row[quantity] == "optical-depth" && !field) {  // the CLI tests' aggregate bound for optical depth (see above)
      EXPECT_LT(std::stod(row[rmse]), 1e-3 * std::stod(row[peak])) << row[dataset] << " " << row[settings];
    }
    if (row[sweep] == "mixed") mixed_rmse[row[mode] + "/" + row[settings]] = std::stod(row[rmse]);
    else if (row[dataset].rfind("default", 0) == 0) {
      default_rmse[row[quantity] + "/" + row[mode] + "/" + row[settings]] = std::stod(row[rmse]);
      default_ssim[row[quantity] + "/" + row[mode] + "/" + row[settings]] = s;
    }
    if (row[sweep] == "march-step" && row[mode] == "interval-march") march_rmse[row[quantity] + "/" + row[settings]] = std::stod(row[rmse]);
    if (row[sweep] == "cells") cell_counts.insert(row[cells]);
    if (row[quantity] == "color") {  // FLIP: 0 identical .. 1; the close images here are near 0
      const double f = std::stod(row[flip]);
      // GI rows carry Monte Carlo noise against a path-traced reference: looser, compared below.
      // VTK's mappers blend in 8 bits, and on colour's near-black default background FLIP (which
      // compares in a perceptual space that spreads dark values apart) sees their 1/255 steps:
      // up to 0.1. The analytic field's tetrahedra are not close to the field (see above).
      const bool gi = row[mode].rfind("htex-", 0) == 0;
      const bool eight_bit = row[mode].rfind("vtk-", 0) == 0;
      const double bound = gi ? 0.25 : (eight_bit || field) ? 0.1 : 0.05;
      EXPECT_TRUE(f >= 0.0 && f < bound) << row[dataset] << " " << row[mode] << " flip " << f;
      if (row[sweep] == "surfaces") flip_of[row[mode] + "/" + row[settings].substr(0, row[settings].find(' '))] = f;
      if (row[dataset].rfind("default", 0) == 0 && row[sweep] != "mixed") flip_of[row[mode] + "/" + row[settings]] = f;
    } else {
      EXPECT_EQ(row[flip], "") << row[quantity];
    }
    if (row[timer] == "wall") peers.insert(row[quantity] + "/" + row[mode]);
    else EXPECT_EQ(row[timer], "gpu");
  }
  EXPECT_EQ(peers, (std::multiset<std::string>{"color/vtk-projected-tetrahedra", "color/vtk-ray-cast", "color/vtk-zsweep",
                                                "transmittance/vtk-projected-tetrahedra", "transmittance/vtk-ray-cast",
                                                "transmittance/vtk-zsweep"}));
  // The compute backend composites each pixel in its own depth order: as accurate as the exact
  // order on the mesh-shader backend (same reference, same aggregate; the two differ only in
  // float rounding), and better than mesh order.
  const std::string compute = "volume-backend=compute";
  ASSERT_TRUE(default_rmse.count("color/interval-exact-order/" + compute)) << slurp(dir / "bench.csv");
  EXPECT_LT(default_rmse.at("color/interval-exact-order/" + compute), 2.0 * default_rmse.at("color/interval-exact-order/default") + 1e-5);
  EXPECT_LT(default_rmse.at("color/interval-exact-order/" + compute), default_rmse.at("color/interval/default"));
  EXPECT_LT(default_rmse.at("optical-depth/interval/" + compute), 2.0 * default_rmse.at("optical-depth/interval/default") + 1e-6);
  // The perceptual metric agrees with RMSE that exact order beats mesh order.
  EXPECT_LT(flip_of.at("interval-exact-order/default"), flip_of.at("interval/default"));
  EXPECT_EQ(sweeps, (std::set<std::string>{"modes", "tetlet-size", "preintegration", "march-step", "cells", "surfaces", "mixed"}));
  // Mixed rows: every surface mode without indirect light under the volume, on both backends, in
  // exact order against the mixed reference; the compute backend composites each pixel in its own
  // depth order, as accurate as exact order on the mesh backend (as the volume rows above).
  for (const char* surface : {"forward", "htex", "texel", "msa", "fastatlas"}) {
    const std::string m = std::string("interval-exact-order+") + surface;
    ASSERT_TRUE(mixed_rmse.count(m + "/volume-backend=mesh") && mixed_rmse.count(m + "/volume-backend=compute")) << m;
    EXPECT_LT(mixed_rmse.at(m + "/volume-backend=compute"), 2.0 * mixed_rmse.at(m + "/volume-backend=mesh") + 1e-5) << m;
  }
  EXPECT_EQ(mixed_rmse.size(), 10u);
  // Surface rows: each mode with shadows off and on, against the CPU direct light; the shaded
  // samples are counted (forward: the covered pixels; htex, texel, msa, fastatlas: texels, at about the same rate).
  std::set<std::string> surface_configurations;
  const size_t shaded = column("shaded");
  for (const auto& row : rows)
    if (row[sweep] == "surfaces") {
      EXPECT_EQ(row[dataset], "cornell-box");
      surface_configurations.insert(row[mode] + "/" + row[settings].substr(0, row[settings].find(' ')));
      EXPECT_GT(std::stoull(row[shaded]), 128u * 96u / 4) << row[mode];
      // Compared as displayed (radiance clamped to [0, 1], peak 1): every row read RMSE 0.251 in
      // linear radiance, 90% of it from an aliased light edge at radiance 17.
      EXPECT_EQ(std::stod(row[peak]), 1.0) << row[mode];
      EXPECT_LT(std::stod(row[rmse]), 0.1) << row[mode] << " " << row[settings];
      EXPECT_LT(std::stoull(row[shaded]), 128u * 96u * 8) << row[mode];
    }
  // Reuse pays: after the same frames, ReSTIR GI's image is perceptually closer to the path
  // tracer than one fresh bounce sample per texel.
  EXPECT_LT(flip_of.at("htex-gi/shadows=on"), flip_of.at("htex-pt/shadows=on"));
  EXPECT_EQ(surface_configurations,
            (std::set<std::string>{"forward/shadows=off", "forward/shadows=on", "htex/shadows=off", "htex/shadows=on", "htex-gi/shadows=on",
                                   "htex-gi-unbiased/shadows=on", "htex-pt/shadows=on", "texel/shadows=off", "texel/shadows=on", "msa/shadows=off", "msa/shadows=on",
                                   "fastatlas/shadows=off", "fastatlas/shadows=on"}));
  // FastAtlas at one texel per pixel puts every pixel centre on a texel centre: its error is the
  // forward backend's.
  for (const char* shadows : {"off", "on"})
    EXPECT_NEAR(flip_of.at(std::string("fastatlas/shadows=") + shadows), flip_of.at(std::string("forward/shadows=") + shadows), 2e-3) << shadows;
  EXPECT_EQ(cell_counts, (std::set<std::string>{"1296", "10368"}));  // 6 * N^3 for N = 6, 12
  // The march's midpoint rule converges: a 4x finer step is more accurate for either quantity.
  ASSERT_EQ(march_rmse.size(), 4u);
  for (const char* q : {"optical-depth", "color"})
    EXPECT_LT(march_rmse.at(std::string(q) + "/march-step=diagonal/100"), march_rmse.at(std::string(q) + "/march-step=diagonal/25")) << q;
  ASSERT_EQ(default_rmse.size(), 13u);  // 7 of our configurations, 3 on the compute backend and VTK's 3
  // Exact visibility order removes the compositing-order error mesh order makes.
  EXPECT_LT(default_rmse.at("color/interval-exact-order/default"), default_rmse.at("color/interval/default"));
  EXPECT_GT(default_ssim.at("color/interval-exact-order/default"), default_ssim.at("color/interval/default"));
  const std::string report = slurp(dir / "report.md");
  EXPECT_NE(report.find("| * |"), std::string::npos) << report;
  EXPECT_NE(report.find("bench --quick"), std::string::npos) << report;
  // Every plot the report links exists as a PNG: the error-time plots and the scaling plot.
  size_t plots = 0;
  for (size_t at = report.find("](", 0); at != std::string::npos; at = report.find("](", at + 2)) {
    const std::string file = report.substr(at + 2, report.find(')', at) - at - 2);
    EXPECT_TRUE(fs::is_regular_file(dir / file) && fs::file_size(dir / file) > 1000) << file;
    ++plots;
  }
  EXPECT_GE(plots, 6u) << report;
  EXPECT_TRUE(fs::is_regular_file(dir / "time_vs_cells.png"));
  // --replot draws the same plots again from the CSV alone (a run on a machine without X).
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".png") fs::remove(entry.path());
  const CliRun replot = run("bench --replot " + dir.string());
  ASSERT_EQ(replot.code, 0) << replot.err;
  const std::string relinked = slurp(dir / "report.md");
  EXPECT_EQ(std::count(relinked.begin(), relinked.end(), '\n') , std::count(report.begin(), report.end(), '\n')) << relinked;
  EXPECT_TRUE(fs::is_regular_file(dir / "time_vs_cells.png"));
  EXPECT_EQ(run("bench --replot " + (dir / "nothing").string()).code, 2);
}

// Moving-camera rows and the meshlet shading atlas's temporal amortization: the amortized row
// shades fewer texels per frame than the moving one that shades every frame (here about a
// quarter: every 4th frame), and it ends at the same camera, so its error is measured where the
// others' is. Each chart kind gets its rows. Bad values name the option.
// The bench's options are checked before any work: a typo in a list, an empty list or an
// impossible number of lights is refused by name (each once was dropped, measured as nothing
// with exit 0, failed 18 s in, or ran out of memory), and no folder is left.
TEST(Cli, BenchRefusesBadListsBeforeAnyWork) {
  const fs::path dir = work_dir() / "bench_lists";
  const std::string out = " --quick --no-peers --no-plots --out " + dir.string();
  expect_refused("bench --sweeps surfaces --surface-modes forward,fastatls" + out, "'fastatls' is not a GPU surface mode");
  expect_refused("bench --sweeps surfaces --surface-modes bogus" + out, "'bogus' is not a GPU surface mode");
  expect_refused("bench --sweeps surfaces --surface-modes path-reference" + out, "'path-reference' is not a GPU surface mode");
  expect_refused("bench --sweeps ," + out, "--sweeps: has an empty item");
  expect_refused("bench --sweeps modes,,cells" + out, "--sweeps: has an empty item");
  expect_refused("bench --sweeps modes --msa-charts bogus" + out, "--msa-charts");
  expect_refused("bench --sweeps surfaces --surface-lights 1000000000" + out, "at most 4096 lights");
  EXPECT_FALSE(fs::exists(dir));
}

TEST(Cli, BenchMovesTheCameraAndAmortizesTheAtlas) {
  const fs::path dir = work_dir() / "bench_motion";
  const CliRun r = run("bench --quick --sweeps surfaces --surfaces cornell-box --surface-modes msa --surface-motion 2 "
                       "--msa-amortize 4 --msa-charts projection,conformal --frames 4 --warm-up 0.25 --no-plots --validate --out " + dir.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::vector<bench::BenchRow> rows = bench::read_csv(dir / "bench.csv");
  EXPECT_NE(slurp(dir / "report.md").find("follow at least 0.25 s of its frames"), std::string::npos);
  for (const char* shadows : {"shadows=off", "shadows=on"}) {
    const bench::BenchRow *moving = nullptr, *amortized = nullptr, *conformal = nullptr;
    for (const auto& row : rows) {
      if (row.settings.rfind(shadows, 0) != 0 || row.settings.find("camera=moving(2deg/frame)") == std::string::npos) continue;
      if (row.settings.find("charts=conformal") != std::string::npos) {
        if (row.settings.find("amortize") == std::string::npos) conformal = &row;
        continue;
      }
      (row.settings.find("amortize=4") != std::string::npos ? amortized : moving) = &row;
    }
    if (std::string(shadows) == "shadows=on" && !moving) continue;  // a device without ray tracing
    ASSERT_NE(moving, nullptr) << shadows;
    ASSERT_NE(amortized, nullptr) << shadows;
    EXPECT_GT(moving->shaded, 0u);
    EXPECT_LT(amortized->shaded, moving->shaded) << shadows;
    EXPECT_TRUE(std::isfinite(amortized->error.rmse));
    ASSERT_NE(conformal, nullptr) << shadows;
    EXPECT_GT(conformal->shaded, 0u);
    EXPECT_TRUE(std::isfinite(conformal->error.rmse));
  }
  // Into a new folder: the one above holds results, which a bench refuses to replace before all else.
  const std::string fresh = (dir / "refused").string();
  expect_refused("bench --quick --sweeps surfaces --msa-charts lscm --out " + fresh, "--msa-charts");
  expect_refused("bench --quick --sweeps surfaces --msa-amortize 4 --out " + fresh, "--msa-amortize");
  expect_refused("bench --quick --sweeps surfaces --warm-up -1 --out " + fresh, "--warm-up");
  expect_refused("bench --quick --sweeps surfaces --surface-motion 0 --out " + fresh, "--surface-motion");
}

TEST(Cli, InfoPlanShowsTheSortOnlyWhereTheQuantityNeedsOne) {
  // The planned passes are the lines between "plan" and "skipped:"; a planned sort is "  sort (GPU): ...".
  auto planned = [](const std::string& out) { return out.substr(0, out.find("skipped:")); };
  const CliRun depth = run("info field:blobs:2 --plan --quantity optical-depth");
  ASSERT_EQ(depth.code, 0) << depth.err;
  EXPECT_EQ(planned(depth.out).find("\n  sort"), std::string::npos) << depth.out;
  EXPECT_NE(planned(depth.out).find("\n  interval-shading (GPU): "), std::string::npos) << depth.out;
  EXPECT_NE(depth.out.find("  sort: optical depth is order-independent"), std::string::npos) << depth.out;
  const CliRun color = run("info field:blobs:2 --plan --quantity color --mode interval-sorted");
  ASSERT_EQ(color.code, 0) << color.err;
  EXPECT_NE(planned(color.out).find("\n  sort (GPU): colour is order-dependent"), std::string::npos) << color.out;
  const CliRun exact = run("info field:blobs:2 --plan --quantity color --mode interval-exact-order --preintegration-size 8");
  ASSERT_EQ(exact.code, 0) << exact.err;
  for (const char* pass : {"\n  preintegrate (CPU): ", "\n  exact-order (CPU): ", "\n  upload-order (GPU): "})
    EXPECT_NE(planned(exact.out).find(pass), std::string::npos) << pass << exact.out;
  EXPECT_EQ(planned(exact.out).find("\n  sort"), std::string::npos) << exact.out;
  EXPECT_EQ(run("info field:blobs:2 --quantity color").code, 2);  // volume options need --plan

  const fs::path stats = work_dir() / "plan.json";
  const CliRun r = run("render field:blobs:2 --quantity color --size 16x12 --frames 2 --output " + (work_dir() / "plan.png").string() +
                       " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string js = slurp(stats);
  // The last timed frame's plan: the warm-up frame uploaded the transfer function already.
  EXPECT_NE(js.find("\"plan\": [\n    {\"name\": \"sort\", \"kind\": \"gpu\", \"reason\": \"colour is order-dependent"),
            std::string::npos) << js;
  EXPECT_NE(js.find("{\"pass\": \"transfer-function upload\", \"reason\": \"transfer function unchanged\"}"), std::string::npos) << js;
  EXPECT_NE(js.find("{\"pass\": \"exact-order\", \"reason\": "), std::string::npos) << js;
  // Timed frames order again (a still camera's reuse would hide what ordering costs).
  EXPECT_NE(js.find("\"passes\": [\n    {\"name\": \"sort\""), std::string::npos) << js;
}

// render --frames N summarizes the timed frames once: every pass's best <= median <= worst in the
// stats and on the terminal, and the SM clock nvidia-smi reported meanwhile (a fake one on PATH
// here, printing three clocks in one write every 0.2 s: the timed frames are shorter than that,
// so the clocks of the warm-up's last half second stand for them, whole triples of them).
TEST(Cli, TimedFramesGiveBestMedianWorstAndTheClock) {
  const fs::path bin = work_dir() / "fake-bin";
  fs::create_directories(bin);
  std::ofstream(bin / "nvidia-smi") << "#!/bin/sh\nwhile true; do printf '1200\\n1300\\n1250\\n'; sleep 0.2; done\n";
  fs::permissions(bin / "nvidia-smi", fs::perms::owner_all);
  const std::string old_path = std::getenv("PATH") ? std::getenv("PATH") : "";
  setenv("PATH", (bin.string() + ":" + old_path).c_str(), 1);
  const fs::path stats = work_dir() / "timed.json";
  const CliRun r = run("render field:blobs:2 --quantity color --size 16x12 --frames 3 --output " + (work_dir() / "timed.png").string() +
                       " --stats " + stats.string());
  setenv("PATH", old_path.c_str(), 1);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json js = nlohmann::json::parse(slurp(stats));
  EXPECT_EQ(js.at("frames"), 3);
  ASSERT_FALSE(js.at("passes").empty());
  for (const auto& p : js.at("passes")) {
    const double best = p.at("min_ms"), median = p.at("gpu_ms"), worst = p.at("max_ms");
    EXPECT_LE(best, median) << p;
    EXPECT_LE(median, worst) << p;
    EXPECT_GT(best, 0.0) << p;
    const std::string name = p.at("name");
    EXPECT_NE(r.out.find("  " + name + ": "), std::string::npos) << r.out;
  }
  EXPECT_NE(r.out.find("(best "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("a whole frame: best "), std::string::npos) << r.out;
  ASSERT_TRUE(js.contains("sm_clock_mhz")) << js;
  EXPECT_EQ(js.at("sm_clock_mhz").at("min"), 1200);
  EXPECT_EQ(js.at("sm_clock_mhz").at("median"), 1250);
  EXPECT_EQ(js.at("sm_clock_mhz").at("max"), 1300);
  const int samples = js.at("sm_clock_mhz").at("samples");
  EXPECT_GE(samples, 3);
  EXPECT_EQ(samples % 3, 0) << "whole triples";
  EXPECT_NE(r.out.find("SM clock: 1200 / 1250 / 1300 MHz"), std::string::npos) << r.out;
}

TEST(Cli, ParaViewColormapFileDrivesTheTransferFunction) {
  const fs::path json = work_dir() / "map.json";
  std::ofstream(json) << R"([{"Name": "two reds", "RGBPoints": [-1, 0.2, 0, 0, 1, 1, 0, 0], "Points": [-1, 0, 0.5, 0, 1, 1, 0.5, 0]}])";
  const fs::path pfm = work_dir() / "reds.pfm";
  const fs::path stats = work_dir() / "reds.json";
  const CliRun r = run("render --quantity color --tf " + json.string() + " --density-scale 20 --background 0,0,0 --size 24x18 "
                       "--output " + pfm.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(slurp(stats).find("\"transfer_function\": \"two reds\""), std::string::npos);
  const io::FloatImage img = io::read_pfm(pfm.string());
  double red = 0.0, other = 0.0;
  for (size_t i = 0; i < img.pixels.size(); i += 3) {
    red += double(img.pixels[i]);
    other += double(img.pixels[i + 1]) + double(img.pixels[i + 2]);
  }
  EXPECT_GT(red, 1.0);      // the medium glows red...
  EXPECT_EQ(other, 0.0);    // ...and nothing else: green and blue are zero in every colour point
}

// A closed surface (OFF) filled with tetrahedra by TetGen renders as the enclosed medium: the
// optical depth through a cube of side 2 with sigma 1 is the chord, whatever the cells.
TEST(Cli, ClosedSurfaceIsTetrahedralizedAndRendered) {
  ::setenv("XDG_CACHE_HOME", (work_dir() / "cache").c_str(), 1);  // a fresh TetGen cache
  const fs::path off = work_dir() / "cube.off";
  std::ofstream(off) << "OFF\n8 12 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n"
                        "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
  const fs::path pfm = work_dir() / "cube.pfm";
  const CliRun r = run("render " + off.string() + " --tetgen-max-volume 0.05 --quantity optical-depth --size 32x24 "
                       "--eye 4,3,5 --target 1,1,1 --output " + pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("tetrahedra by TetGen"), std::string::npos) << r.err;
  const io::FloatImage img = io::read_pfm(pfm.string());
  io::TetgenOptions options;
  options.max_volume = 0.05;
  const TetMesh mesh = io::tetrahedralize(io::read_surface(off.string()), options);
  EXPECT_GE(mesh.tets.size(), 160u);
  Camera c;
  c.eye = {4, 3, 5};
  c.target = {1, 1, 1};
  c.near_distance = fit_camera(bounds_of(mesh)).near_distance;
  expect_close_to_reference(img, reference::optical_depth_image(mesh, c, 32, 24));

  // Reopened with the same options: TetGen's result comes from the cache, the same image.
  const CliRun again = run("render " + off.string() + " --tetgen-max-volume 0.05 --quantity optical-depth --size 32x24 "
                           "--eye 4,3,5 --target 1,1,1 --output " + (work_dir() / "cube2.pfm").string());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("from the cache"), std::string::npos) << again.err;
  EXPECT_EQ(io::read_pfm((work_dir() / "cube2.pfm").string()).pixels, img.pixels);

  // The same cube without its last face: named as open, with the way out; then filled.
  std::string text = slurp(off);
  text.replace(text.find("8 12 0"), 6, "8 11 0");
  text = text.substr(0, text.rfind("3 3 4 7"));
  const fs::path open = work_dir() / "open.off";
  std::ofstream(open) << text;
  expect_refused("render " + open.string() + " --size 8x8 --output " + (work_dir() / "o.png").string(), "--fill-holes");
  const CliRun filled = run("render " + open.string() + " --fill-holes --size 8x8 --output " + (work_dir() / "o.png").string());
  EXPECT_EQ(filled.code, 0) << filled.err;
  // info tells which is which before anything is tetrahedralized.
  const CliRun info_closed = run("info " + off.string()), info_open = run("info " + open.string());
  EXPECT_EQ(info_closed.code, 0) << info_closed.err;
  EXPECT_NE(info_closed.out.find("triangles: 12, points: 8"), std::string::npos) << info_closed.out;
  EXPECT_NE(info_closed.out.find("closed: yes"), std::string::npos) << info_closed.out;
  EXPECT_NE(info_open.out.find("closed: no: 3 boundary"), std::string::npos) << info_open.out;  // one triangle gone
}

// --tetgen-cells aims TetGen at a cell count; bad counts are exit code 2 naming the option.
// Two unit cubes overlapping in a 0.5^3 corner, in one OFF: closed but self-intersecting, so
// TetGen refuses it (exit 2, no file); --remesh H replaces it by its level set's zero crossing,
// which TetGen fills. That surface lies within half a voxel of the true one away from the
// edges, so the volume differs from the union's (2 - 0.125) by at most area x H / 2, the area
// being at most the two cubes' 12.
TEST(Cli, RemeshMakesASelfIntersectingSurfaceTetrahedralizable) {
  const fs::path dir = work_dir() / "remesh";
  fs::create_directories(dir);
  const fs::path off = dir / "two_cubes.off", refused = dir / "refused.vtu", remeshed = dir / "remeshed.vtu";
  {
    std::ofstream out(off);
    out << "OFF\n16 24 0\n";
    for (double o : {0.0, 0.5})
      for (int i = 0; i < 8; ++i)
        out << o + (i == 1 || i == 2 || i == 5 || i == 6) << " " << o + (i == 2 || i == 3 || i == 6 || i == 7) << " " << o + (i >= 4)
            << "\n";
    for (int base : {0, 8})
      for (const std::array<int, 3> f : {std::array<int, 3>{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                         {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}})
        out << "3 " << base + f[0] << " " << base + f[1] << " " << base + f[2] << "\n";
  }
  expect_refused("convert " + off.string() + " " + refused.string(), "intersects itself");
  EXPECT_FALSE(fs::exists(refused));
  const CliRun good = run("convert " + off.string() + " " + remeshed.string() + " --remesh 0.05");
  ASSERT_EQ(good.code, 0) << good.err;
  const TetMesh mesh = io::read_tet_mesh(remeshed.string());
  double volume = 0.0;
  for (const auto& t : mesh.tets)
    volume += std::abs(signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]));
  EXPECT_NEAR(volume, 2.0 - 0.125, 12.0 * 0.05 / 2.0);
  EXPECT_EQ(run("convert " + off.string() + " " + remeshed.string() + " --remesh -1").code, 2);
}

TEST(Cli, TetgenCellsLandsNearTheTargetAndRejectsBadCounts) {
  ::setenv("XDG_CACHE_HOME", (work_dir() / "cache-cells").c_str(), 1);
  const fs::path off = work_dir() / "cube-cells.off";
  std::ofstream(off) << "OFF\n8 12 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n0 0 2\n2 0 2\n2 2 2\n0 2 2\n"
                        "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
  const fs::path vtu = work_dir() / "cube-cells.vtu";
  const CliRun r = run("convert " + off.string() + " " + vtu.string() + " --tetgen-cells 5000");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("(target 5000)"), std::string::npos) << r.err;
  const size_t cells = io::read_tet_mesh(vtu.string()).tets.size();
  EXPECT_LE(std::abs(double(cells) - 5000.0), io::kTargetCellsTolerance * 5000.0) << cells;
  for (const char* bad : {"0", "many", "-3"})
    expect_refused("convert " + off.string() + " " + vtu.string() + " --tetgen-cells " + bad, "--tetgen-cells");
}

// Two unit cubes side by side as legacy hexahedra, with a cell scalar and a point vector.
const char* kTwoHexahedra =
    "# vtk DataFile Version 3.0\nhex\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 12 double\n"
    "0 0 0 1 0 0 1 1 0 0 1 0 0 0 1 1 0 1 1 1 1 0 1 1 2 0 0 2 1 0 2 0 1 2 1 1\n"
    "CELLS 2 18\n8 0 1 2 3 4 5 6 7\n8 1 8 9 2 5 10 11 6\nCELL_TYPES 2\n12\n12\n"
    "CELL_DATA 2\nSCALARS rho double 1\nLOOKUP_TABLE default\n0.5 2\n"
    "POINT_DATA 12\nVECTORS v double\n3 4 0 3 4 0 3 4 0 3 4 0 0 0 1 0 0 1 0 0 1 0 0 1 0 0 2 0 0 2 0 0 2 0 0 2\n";

// A vector array drives the field by magnitude, or by the component asked for: the point
// vector v is (3,4,0) on the left face, (0,0,1) in the middle, (0,0,2) on the right.
TEST(Cli, VectorArraysByMagnitudeOrComponent) {
  const fs::path file = work_dir() / "vectors.vtk";
  std::ofstream(file) << kTwoHexahedra;
  const fs::path pfm = work_dir() / "v.pfm";
  auto total = [&](const std::string& extra) {
    const CliRun r = run("render " + file.string() + " --array v " + extra + " --quantity optical-depth --size 24x16 --eye 1,0.5,6 "
                         "--target 1,0.5,0.5 --output " + pfm.string());
    EXPECT_EQ(r.code, 0) << r.err;
    double sum = 0.0;
    for (float v : io::read_pfm(pfm.string()).pixels) sum += double(v);
    return sum;
  };
  const double magnitude = total(""), x = total("--component x"), y = total("--component 1");
  EXPECT_GT(magnitude, 0.0);
  EXPECT_GT(x, 0.0);
  EXPECT_NEAR(y / x, 4.0 / 3.0, 1e-4);  // linear in the values: components 4 and 3 where non-zero
  expect_refused("render " + file.string() + " --array v --component 5 --size 8x8 --output " + pfm.string(), "has 3 components");
}

// ball[:S]: the constant-extinction ball, whose optical depth at the centre pixel of a view
// through its centre is sigma times the chord across the polyhedron: at most the vertices'
// diameter 2, and at least 2 cos(largest edge angle): every face of the 3-times subdivided
// icosahedron lies beyond radius cos(8 degrees) > 0.99, so 0.98 holds with room.
TEST(Cli, BallDatasetHasTheClosedFormChord) {
  const fs::path pfm = work_dir() / "ball.pfm";
  const CliRun r = run("render ball:3 --density-scale 0.5 --quantity optical-depth --size 33x33 --eye 0,0,5 --target 0,0,0 "
                       "--output " + pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("1280 cells"), std::string::npos) << r.out;
  const float centre = io::read_pfm(pfm.string()).at(16, 16);
  EXPECT_LE(centre, 0.5f * 2.0f * (1.0f + 1e-5f));
  EXPECT_GE(centre, 0.5f * 2.0f * 0.98f);
}

TEST(Cli, InfoDescribesTheFileAndWhatReadingItProduces) {
  const fs::path file = work_dir() / "two_hex.vtk";
  std::ofstream(file) << kTwoHexahedra;
  const CliRun r = run("info " + file.string());
  ASSERT_EQ(r.code, 0) << r.err;
  io::MeshConversion conversion;
  const TetMesh mesh = io::read_tet_mesh(file.string(), {}, &conversion);
  for (const std::string& expected : {
           std::string("cells: 2 (2 vtkHexahedron)"), std::string("points: 12"),
           std::string("bounds: [0, 2] x [0, 1] x [0, 1]"),
           std::string("rho: [0.5, 2]"),                           // the cell values as written
           std::string("v: [1, 5] (magnitude of 3 components)"),  // |(3,4,0)| = 5, |(0,0,1)| = 1
           "split 2 vtkHexahedron into " + std::to_string(mesh.tets.size()) + " tetrahedra",
           std::string("volume 2\n"),  // two unit cubes
           std::string("zero-volume tetrahedra: 0"), std::string("inverted tetrahedra: 0"),
           // 24 B per tetrahedron and 16 B per point, from the upload in interval_shading.cpp
           "GPU memory (mesh buffers): " + std::to_string(24 * mesh.tets.size() + 16 * 12) + " B"})
    EXPECT_NE(r.out.find(expected), std::string::npos) << "missing '" << expected << "' in\n" << r.out;
  EXPECT_EQ(run("info --help").code, 0);
}

TEST(Cli, RenderNotesTheSplitAndTheFlatAndInvertedCells) {
  const fs::path hex = work_dir() / "note_hex.vtk";
  std::ofstream(hex) << kTwoHexahedra;
  const CliRun r = run("render " + hex.string() + " --output " + (work_dir() / "note.pfm").string() + " --mode reference --size 8x8");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("note: " + hex.string() + ": split 2 vtkHexahedron into"), std::string::npos) << r.err;
  // A sound tetrahedron, the same inverted, and a flat one: all kept, two reported.
  const fs::path quality = work_dir() / "quality.vtk";
  std::ofstream(quality) << "# vtk DataFile Version 3.0\nq\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 5 double\n"
                            "0 0 0 1 0 0 0 1 0 0 0 1 1 1 0\nCELLS 3 15\n4 0 1 2 3\n4 1 0 2 3\n4 0 1 2 4\nCELL_TYPES 3\n10\n10\n10\n";
  const CliRun q = run("render " + quality.string() + " --output " + (work_dir() / "q.pfm").string() + " --mode reference --size 8x8");
  ASSERT_EQ(q.code, 0) << q.err;
  EXPECT_NE(q.err.find("1 zero-volume tetrahedra (kept"), std::string::npos) << q.err;
  EXPECT_NE(q.err.find("1 inverted tetrahedra"), std::string::npos) << q.err;
  const CliRun i = run("info " + quality.string());
  EXPECT_NE(i.out.find("zero-volume tetrahedra: 1"), std::string::npos) << i.out;
  EXPECT_NE(i.out.find("inverted tetrahedra: 1"), std::string::npos) << i.out;
}

// Broken mesh files, written into the scratch folder; each name says what is wrong.
void write_bad_meshes() {
  const fs::path d = work_dir();
  const std::string two = kTwoHexahedra;
  std::ofstream(d / "legacy_content.vtu") << two;
  std::ofstream(d / "header.vtk") << std::string(two).replace(two.find("UNSTRUCTURED_GRID"), 17, "UNSTRUCTURED_GRIM");
  std::ofstream(d / "range.vtk") << std::string(two).replace(two.find("8 1 8 9"), 7, "8 1 8 90");
  std::ofstream(d / "empty.vtk") << "# vtk DataFile Version 3.0\ne\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 0 double\nCELLS 0 0\nCELL_TYPES 0\n";
  fs::create_directories(d / "folder.vtu");
  TetMesh box = make_box_mesh(glm::dvec3(0), glm::dvec3(1), 1, [](const glm::dvec3&) { return 1.0; });
  io::write_tet_mesh_vtu((d / "good.vtu").string(), box);
  std::ofstream(d / "xml_content.vtk") << slurp(d / "good.vtu");
  const std::string whole = slurp(d / "good.vtu");
  std::ofstream(d / "truncated.vtu") << whole.substr(0, whole.size() / 2);
  box.points[0].y = std::nan("");
  io::write_tet_mesh_vtu((d / "nan.vtu").string(), box);
  box.points[0].y = INFINITY;
  io::write_tet_mesh_vtu((d / "inf.vtu").string(), box);
}

TEST(Cli, BadInputExitsWithTwoAndNamesTheProblem) {
  write_bad_meshes();
  const std::string d = work_dir().string() + "/";
  struct Case { std::string args, fragment; };
  const std::vector<Case> cases = {
      {"info /no/such/file.vtu", "/no/such/file.vtu: file does not exist"},
      {"info " + d + "folder.vtu", "folder.vtu: is not a regular file"},
      {"info " + d + "legacy_content.vtu", "holds a legacy VTK file: its extension should be .vtk"},
      {"info " + d + "xml_content.vtk", "holds a VTK XML UnstructuredGrid: its extension should be .vtu"},
      {"info " + d + "truncated.vtu", "truncated.vtu: VTK could not read the file (truncated or corrupt?)"},
      {"info " + d + "header.vtk", "not an UNSTRUCTURED_GRID"},
      {"info " + d + "nan.vtu", "point 0 has a non-finite coordinate"},
      {"render --output x.png " + d + "inf.vtu", "point 0 has a non-finite coordinate"},
      {"render --output x.png --frames 99999999999999999999", "--frames: '99999999999999999999' is too large (at most 4294967295)"},
      {"render --output x.png --frames 12x", "--frames: '12x' is not a whole number"},
      {"render --output x.png --up 0,0,0", "up vector is zero"},
      {"view --frames 0", "--frames: must be at least 1"},
      {"info " + d + "range.vtk", "uses point 90 but there are 12 points (index out of range)"},
      {"info " + d + "empty.vtk", "has no cells (empty mesh)"},
      {"render --output x.png " + d + "good.vtu --array nope", "has no array 'nope' (cell arrays: extinction"},
      {"info", "expects one FILE"},
      {"render --output x.png --size 0x5", "--size"},
      {"render --output x.tiff", "x.tiff"},
      {"render --output x.png --eye 1,2", "--eye"},
      {"render --output x.png --fovy abc", "--fovy"},
      {"render --output x.png --eye 0,0,0 --target 0,0,0", "camera"},
      {"render --output x.png /no/such/file.vtu", "/no/such/file.vtu: file does not exist"},
      {"render --output x.png --array rho", "--array"},
      {"convert out.stl", "out.stl"},
      {"convert /no/such/dir/out.vtu", "/no/such/dir/out.vtu"},
      {"render --output x.png --mode nonsense", "--mode"},
      {"render --output x.png --bogus", "--bogus"},
      {"render", "--output"},
      {"frobnicate", "frobnicate"},
      {"render --output /no/such/dir/x.png --size 8x8", "/no/such/dir/x.png"},
      {"render --output x.png --quantity color --tf no-such-map", "no-such-map"},
      {"render --output x.png --quantity color --tf-range 5,1", "--tf-range"},
      {"render --output x.png --quantity color --preintegration-size 1", "--preintegration-size"},
      {"render --output x.png --quantity optical-depth --tf viridis", "--tf"},
      {"render --output x.png --quantity colour", "--quantity"},
      {"render --output x.png --quantity color --background 2,0,0", "--background"},
      {"render --output x.png --size 8x8 --shared-vertices --tetlet-size 1", "--shared-vertices"},
      {"render --output x.png --size 8x8 --shared-vertices --quantity color", "--shared-vertices"},
      {"render --output x.png --size 8x8 --tetlet-size 3", "--tetlet-size"},
      {"render --output x.png --size 8x8 --volume-backend gpu", "--volume-backend"},
      {"render --output x.png --size 8x8 --volume-backend compute --shared-vertices", "--shared-vertices"},
      {"render --output x.png --size 8x8 --subsample 2", "--subsample"},
      {"render --output x.png --size 8x8 /no/such.vti --subsample 0", "--subsample"},
      {"render --output x.png --size 8x8 /no/such.vti", "/no/such.vti"},
      {"render --output x.png --size 8x8 --fill-holes", "--fill-holes"},
      {"render --output x.png --size 8x8 /no/such.stl", "/no/such.stl"},
      {"render field:marschner-lobb --output x.png --mode interval-march --isovalue 0.3", "--isovalue"},
      {"render field:marschner-lobb --output x.png --mode interval-march --march-step 0", "--march-step"},
      {"render field:marschner-lobb --output x.png --mode interval-march --march-step -0.1", "--march-step"},
      {"render field:marschner-lobb --output x.png --mode interval-march --march-step 1e-9", "--march-step"},
      {"render field:no-such-field --output x.png --mode interval-march", "field:no-such-field"},
      {"render field:sphere --output x.png --quantity isosurface", "--quantity isosurface"},
      {"render --output x.png --mode interval-march", "--mode interval-march"},
      {"render field:sphere:0 --output x.png", "field:sphere:0"},
      {"render ball:9 --output x.png", "ball:9"},
      {"render grid:sphere:1 --output x.png", "grid:sphere:1"},
      {"render grid:no-such-field --output x.png --mode interval-march", "grid:no-such-field: unknown analytic field"},
      {"render grid:sphere --output x.png --array density", "--array"},
  };
  for (const auto& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.fragment), std::string::npos) << c.args << " printed: " << r.err;
  }
}

TEST(Cli, MissingDeviceExitsWithThree) {
  const CliRun r = run("render --output x.png --device 99");
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("--device 99"), std::string::npos) << r.err;
}

TEST(Cli, ViewExitsCleanlyOnSigterm) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "needs a display: run through scripts/test.sh (Xvfb)";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::freopen("/dev/null", "w", stdout);
    execl(PRISMOID_EXE, PRISMOID_EXE, "view", "--validate", "--size", "200x150", static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::seconds(3));
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  int status = 0;
  const auto start = std::chrono::steady_clock::now();
  pid_t done = 0;
  while ((done = waitpid(pid, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() - start < std::chrono::seconds(10))
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  if (done == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
    FAIL() << "prismoid view did not exit within 10 s of SIGTERM";
  }
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  EXPECT_EQ(WEXITSTATUS(status), 0);
}

// The surface window shares the volume window's frame loop, SIGTERM and SIGINT handling
// included: each signal, sent once the window draws (its first timings line on stdout), closes it
// as the window's close button does, exit 0 with a clean validation log, as the volume window.
TEST(Cli, SurfaceViewExitsCleanlyOnSigtermAndSigint) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "needs a display: run through scripts/test.sh (Xvfb)";
  for (const int sig : {SIGTERM, SIGINT}) {
    int out[2];
    ASSERT_EQ(pipe(out), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      dup2(out[1], STDOUT_FILENO);
      close(out[0]);
      close(out[1]);
      execl(PRISMOID_EXE, PRISMOID_EXE, "view", "cornell-box", "--validate", "--size", "200x150", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(out[1]);
    // Up to a minute for the window to draw (lavapipe, a loaded machine): it prints a line a second.
    std::string seen;
    const auto start = std::chrono::steady_clock::now();
    while (seen.find("Prismoid - ") == std::string::npos && std::chrono::steady_clock::now() - start < std::chrono::seconds(60)) {
      char buffer[256];
      const ssize_t n = read(out[0], buffer, sizeof(buffer));
      if (n <= 0) break;
      seen.append(buffer, size_t(n));
    }
    ASSERT_NE(seen.find("Prismoid - "), std::string::npos) << "the surface window drew nothing: " << seen;
    ASSERT_EQ(kill(pid, sig), 0);
    int status = 0;
    const auto sent = std::chrono::steady_clock::now();
    pid_t done = 0;
    while ((done = waitpid(pid, &status, WNOHANG)) == 0 && std::chrono::steady_clock::now() - sent < std::chrono::seconds(10))
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    close(out[0]);
    if (done == 0) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      FAIL() << "prismoid view cornell-box did not exit within 10 s of signal " << sig;
    }
    ASSERT_TRUE(WIFEXITED(status)) << "signal " << sig << ": killed by signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    EXPECT_EQ(WEXITSTATUS(status), 0) << "signal " << sig;
  }
}

}  // namespace
}  // namespace prismoid

namespace prismoid {
namespace {

TEST(Cli, PathReferenceRendersTheFurnaceAtItsClosedForm) {
  // furnace:0.5 has radiance Le / (1 - A) = 2 everywhere; the image average of 16x16 pixels x
  // 64 samples is within 4 standard errors (from the --variance image) of it, plus the depth
  // cap's bias Le A^31 / (1 - A) ~ 1e-9.
  const fs::path pfm = work_dir() / "furnace.pfm", var = work_dir() / "furnace-var.pfm", stats = work_dir() / "furnace.json";
  const CliRun r = run("render furnace:0.5 --mode path-reference --size 16x16 --spp 64 --max-bounces 30 --output " + pfm.string() +
                       " --variance " + var.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("0 non-finite samples"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string()), v = io::read_pfm(var.string());
  ASSERT_EQ(img.channels, 3u);
  ASSERT_EQ(img.width, 16u);
  ASSERT_EQ(v.pixels.size(), img.pixels.size());
  double sum = 0.0, var_sum = 0.0;
  for (size_t i = 0; i < img.pixels.size(); i += 3) {
    sum += double(img.pixels[i]);
    var_sum += double(v.pixels[i]) / 64.0;
  }
  const double n = double(img.pixels.size() / 3);
  EXPECT_NEAR(sum / n, 2.0, 4.0 * std::sqrt(var_sum) / n + 1e-6);
  EXPECT_GT(var_sum, 0.0);
  const std::string js = slurp(stats);
  EXPECT_NE(js.find("\"samples_per_pixel\": 64"), std::string::npos) << js;
  EXPECT_NE(js.find("\"non_finite\": 0"), std::string::npos) << js;
}

TEST(Cli, PathReferenceLightsASurfaceFileThatHasNoLights) {
  const fs::path off = work_dir() / "lit-cube.off", pfm = work_dir() / "lit-cube.pfm";
  {
    std::ofstream out(off);
    out << "OFF\n8 12 0\n";
    for (int i = 0; i < 8; ++i) out << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    for (const char* f : {"0 1 3", "0 3 2", "4 6 7", "4 7 5", "0 4 5", "0 5 1", "2 3 7", "2 7 6", "0 2 6", "0 6 4", "1 5 7", "1 7 3"})
      out << "3 " << f << "\n";
  }
  const CliRun r = run("render " + off.string() + " --mode path-reference --size 12x12 --spp 8 --eye 2,1.5,3 --output " + pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("default key light (it casts shadows) and sky"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string());
  for (float value : img.pixels) EXPECT_GT(value, 0.0f);  // never black: the cube and the sky behind it

  expect_refused("render furnace:1.5 --mode path-reference --output " + pfm.string(), "furnace:1.5: the furnace's albedo must lie in [0, 1)");
  expect_refused("render field:blobs --mode path-reference --output " + pfm.string(), "renders surfaces");
}

}  // namespace
}  // namespace prismoid
