// Numbers at the edge of float precision through the CLI (docs/user-guide.md, "Bad input and
// hard cases"): a frame whose answer float32 cannot hold is refused (exit 2, the option or
// dataset and the limit named, nothing written); one float renders only approximately is
// written with a warning on stderr and in the stats JSON; no image written holds NaN or Inf.
// The numbers themselves are tested against the reference in tests/volume and tests/surface.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "io/image_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/tet_mesh.hpp"
#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::slurp;
using test::cli::run;
using test::cli::work_dir;

void expect_refused_writing_nothing(const std::string& args, const fs::path& output, const std::string& says) {
  fs::remove(output);
  const CliRun r = run(args + " --output " + output.string());
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(says), std::string::npos) << args << " printed: " << r.err;
  EXPECT_FALSE(fs::exists(output)) << args;
}

void expect_all_finite(const fs::path& pfm) {
  const io::FloatImage img = io::read_pfm(pfm.string());
  size_t non_finite = 0;
  for (float v : img.pixels) non_finite += std::isfinite(v) ? 0 : 1;
  EXPECT_EQ(non_finite, 0u) << pfm;
}

TEST(CliNumbers, OpticalDepthBeyondFloatIsRefusedAndTransmittanceRendersFinite) {
  const fs::path pfm = work_dir() / "dense.pfm";
  for (const char* mode : {"interval", "reference"})
    expect_refused_writing_nothing(std::string("render --size 16x16 --density-scale 1e300 --quantity optical-depth --mode ") + mode,
                                   pfm, "optical depths up to 2.15e+301");
  expect_refused_writing_nothing("render field:blobs --mode interval-march --size 16x16 --density-scale 1e300 --quantity optical-depth",
                                 pfm, "--density-scale");
  for (const std::string args : {"render --size 16x16 --density-scale 1e300", "render --size 16x16 --density-scale 1e300 --quantity color",
                                 "render field:blobs --mode interval-march --size 16x16 --density-scale 1e300",
                                 "render --size 16x16 --quantity color --tf-range -1e300,1e300"}) {
    const CliRun r = run(args + " --output " + pfm.string());
    ASSERT_EQ(r.code, 0) << args << "\n" << r.err;
    expect_all_finite(pfm);
  }
}

TEST(CliNumbers, RangesAndCamerasBeyondFloatAreRefused) {
  const fs::path png = work_dir() / "refused.png";
  expect_refused_writing_nothing("render --size 16x16 --quantity color --tf-range 0,1e-40", png, "--tf-range");
  expect_refused_writing_nothing("render --size 16x16 --fovy 1e-20", png, "--fovy 1e-20");
  expect_refused_writing_nothing("render --size 16x16 --near 1e-25", png, "raise --near");
  expect_refused_writing_nothing("render --size 16x16 --eye 0,0,1e31", png, "2^100");
}

TEST(CliNumbers, PositionsFloatRoundsBeyondAPixelRenderWithAWarning) {
  // A cell 10^6 tall with corners off float's grid at its centre (1/32 apart there), seen from
  // 5 units: rendered, and the warning says by how much it can be off.
  TetMesh tall;
  tall.name = "tall";
  const glm::dvec3 b(0.1234567, 0.3, 0.77777);
  tall.points = {b, b + glm::dvec3(1, 0, 0), b + glm::dvec3(0, 1, 0), b + glm::dvec3(0, 0, 1e6)};
  tall.tets = {{0, 1, 2, 3}};
  tall.cell_extinction = {1.0};
  const fs::path vtu = work_dir() / "tall.vtu", pfm = work_dir() / "tall.pfm", stats = work_dir() / "tall.json";
  io::write_tet_mesh_vtu(vtu.string(), tall);
  const std::string camera = " --size 32x32 --eye 0.32,-4.7,1.27 --target 0.32,0.3,1.27 --up 0,0,1 --near 0.01";
  const CliRun r = run("render " + vtu.string() + camera + " --quantity optical-depth --output " + pfm.string() + " --stats " +
                       stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("prismoid: warning: the GPU's float32 positions"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("world units across the view"), std::string::npos) << r.err;
  const std::string js = slurp(stats);
  EXPECT_NE(js.find("\"warnings\": [\"the GPU's float32 positions"), std::string::npos) << js;
  expect_all_finite(pfm);
  // An ordinary frame has an empty list.
  ASSERT_EQ(run("render --size 16x16 --output " + pfm.string() + " --stats " + stats.string()).code, 0);
  EXPECT_NE(slurp(stats).find("\"warnings\": []"), std::string::npos) << slurp(stats);
}

// Surfaces: an emission of 1e300 is refused by every surface mode before anything is written
// (float32 on the GPU and in every image would hold it as Inf); at a large emission float holds,
// images are finite.
TEST(CliNumbers, SurfaceEmissionBeyondFloatIsRefusedByEveryMode) {
  const fs::path pfm = work_dir() / "furnace.pfm";
  for (const char* mode : {"forward", "path-reference", "htex", "texel", "msa"})
    expect_refused_writing_nothing(std::string("render furnace:0.5:1e300 --size 8x8 --mode ") + mode, pfm,
                                   "material 0 (furnace): emission 1e+300 is beyond 7.92e+28");
  for (const char* mode : {"forward", "path-reference --spp 4"}) {
    const CliRun r = run(std::string("render furnace:0.5:1e28 --size 8x8 --mode ") + mode + " --output " + pfm.string());
    ASSERT_EQ(r.code, 0) << mode << "\n" << r.err;
    expect_all_finite(pfm);
  }
}

}  // namespace
}  // namespace prismoid
