// End-to-end: `prismoid render SCENE --mode forward` as a user runs it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "io/image_io.hpp"
#include "support/cli_run.hpp"
#include "renderer/reference/direct_light.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::slurp;
fs::path work_dir() { return test::cli_work_dir(); }
CliRun run(const std::string& args) { return test::run_cli(args); }
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new test::CliScratchCleanup);

// Seen from inside, the furnace's direct light is Le (1 + A) = 1.5 at every pixel. 3e-4 is the
// float rounding bound tests/surface derives for this scene: 1279 area-light terms summed.
TEST(CliForward, RendersTheFurnaceAtItsClosedFormWithStats) {
  const fs::path pfm = work_dir() / "furnace.pfm", stats = work_dir() / "furnace.json";
  const CliRun r = run("render furnace:0.5 --mode forward --quantity color --size 16x12 --validate --output " + pfm.string() +
                       " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const io::FloatImage img = io::read_pfm(pfm.string());
  ASSERT_EQ(img.channels, 3u);
  ASSERT_EQ(img.width, 16u);
  ASSERT_EQ(img.height, 12u);
  for (float v : img.pixels) EXPECT_NEAR(v, 1.5, 3e-4);
  const std::string js = slurp(stats);
  for (const char* key : {"\"mode\": \"forward\"", "\"name\": \"depth pre-pass\"", "\"name\": \"forward shading\"", "\"covered_pixels\": 192",
                          "\"emitters\": 1280", "\"validation_messages\": 0"})
    EXPECT_NE(js.find(key), std::string::npos) << key << " in " << js;
  if (js.find("\"fragments\"") != std::string::npos) {  // pipeline statistics: one shading invocation per pixel
    EXPECT_NE(js.find("\"fragments\": 192"), std::string::npos) << js;
  }
}

// Supersampled, the image is the average over the 2 x 2 sub-pixel points: the CPU reference
// averaged the same way, within 1e-3 of the peak in RMSE (per-pixel tolerances are checked in
// tests/surface; pixels on an edge may keep either side there).
TEST(CliForward, SupersampledCornellBoxAveragesTheReference) {
  const fs::path pfm = work_dir() / "cornell.pfm", png = work_dir() / "cornell.png";
  const CliRun r = run("render cornell-box --mode forward --size 32x32 --supersample 2 --output " + pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2x2 supersampled"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string());
  const SurfaceScene scene = make_cornell_box();
  const auto ref = reference::supersampled_direct_light(scene, scene.camera, 32, 32, 2);
  double peak = 0.0, sq = 0.0;
  for (size_t i = 0; i < ref.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      peak = std::max(peak, ref[i][c]);
      const double d = double(img.pixels[i * 3 + c]) - ref[i][c];
      sq += d * d;
    }
  EXPECT_GT(peak, 1.0);
  EXPECT_LT(std::sqrt(sq / double(ref.size() * 3)), 1e-3 * peak);
  EXPECT_EQ(run("render cornell-box --mode forward --size 24x16 --output " + png.string()).code, 0);
  EXPECT_TRUE(fs::exists(png));
}

// A surface file has no lights: the default headlight and sky light it, and the sky is seen
// around it, so no pixel is black.
TEST(CliForward, LightsASurfaceFileThatHasNoLights) {
  const fs::path off = work_dir() / "cube.off", pfm = work_dir() / "cube.pfm";
  {
    std::ofstream out(off);
    out << "OFF\n8 12 0\n";
    for (int i = 0; i < 8; ++i) out << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    for (const char* f : {"0 1 3", "0 3 2", "4 6 7", "4 7 5", "0 4 5", "0 5 1", "2 3 7", "2 7 6", "0 2 6", "0 6 4", "1 5 7", "1 7 3"})
      out << "3 " << f << "\n";
  }
  const CliRun r = run("render " + off.string() + " --mode forward --size 20x20 --eye 2,1.5,3 --output " + pfm.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("default headlight and sky"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string());
  for (float v : img.pixels) EXPECT_GT(v, 0.0f);
}

TEST(CliForward, BadInputExitsWithTwoAndNamesTheProblem) {
  const std::string out = (work_dir() / "x.pfm").string();
  const std::pair<std::string, std::string> cases[] = {
      {"render cornell-box --mode forward --quantity optical-depth --output " + out, "--quantity"},
      {"render cornell-box --mode forward --supersample 0 --output " + out, "--supersample"},
      {"render field:blobs --mode forward --output " + out, "renders surfaces"},
      {"render furnace:2 --mode forward --output " + out, "furnace:2"},
      {"render cornell-box --mode forward --output x.tiff", "x.tiff"},
      {"render /no/such.stl --mode forward --output " + out, "/no/such.stl"},
  };
  for (const auto& [args, needle] : cases) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
  }
}

}  // namespace
}  // namespace prismoid
