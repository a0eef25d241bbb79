// What the command line says back to a careless user (issue "Nothing a user owns is lost,
// nothing is silently wrong", its smaller findings): a camera that sees none of the data
// warns; messages name what the user typed (the option, the scene), not the verb that happened
// to parse it; `info --plan` takes and checks what render takes; `--` ends the options.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "io/vtk_tet_io.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::slurp;
using test::cli::run;
using test::cli::work_dir;

bool says(const CliRun& r, const std::string& text) { return r.err.find(text) != std::string::npos; }

// `--near 100` on data of size 1 wrote an all-background image without a word.
TEST(CliRefusals, ACameraThatSeesNoneOfTheDataWarns) {
  const fs::path pfm = work_dir() / "none.pfm", stats = work_dir() / "none.json";
  for (const char* mode : {"interval", "reference"}) {
    const CliRun r = run(std::string("render --size 16x16 --near 100 --mode ") + mode + " --output " + pfm.string() + " --stats " +
                         stats.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(says(r, "prismoid: warning: camera: the near plane (--near 100) lies beyond the data's farthest depth")) << mode << ": "
                                                                                                                       << r.err;
    EXPECT_NE(slurp(stats).find("the near plane (--near 100)"), std::string::npos) << slurp(stats);
  }
  const CliRun behind = run("render --size 16x16 --eye 0,0,5 --target 0,0,10 --output " + pfm.string());
  ASSERT_EQ(behind.code, 0) << behind.err;
  EXPECT_TRUE(says(behind, "camera: the data lie behind the eye")) << behind.err;
  const CliRun seen = run("render --size 16x16 --output " + pfm.string());
  ASSERT_EQ(seen.code, 0) << seen.err;
  EXPECT_FALSE(says(seen, "warning")) << seen.err;
}

TEST(CliRefusals, MessagesNameWhatTheUserTyped) {
  const fs::path png = work_dir() / "named.png";
  // A surface mode's scene problem, through info as through render: the mode, not "render:".
  const CliRun plan = run("info --plan --mode msa");
  EXPECT_EQ(plan.code, 2);
  EXPECT_TRUE(says(plan, "--mode msa: draws one surface scene")) << plan.err;
  EXPECT_FALSE(says(plan, "render:")) << plan.err;
  // --reference-error is a volume option: said so for surface modes, not "unknown option".
  const CliRun surface = run("render cornell-box --mode forward --reference-error --size 16x16 --output " + png.string());
  EXPECT_EQ(surface.code, 2);
  EXPECT_TRUE(says(surface, "--reference-error: compares volume modes")) << surface.err;
  const CliRun path = run("render cornell-box --mode path-reference --reference-error --size 16x16 --output " + png.string());
  EXPECT_EQ(path.code, 2);
  EXPECT_TRUE(says(path, "is the reference itself")) << path.err;
  // A built-in surface scene with a volume mode: not "file does not exist".
  const CliRun volume = run("render cornell-box --mode interval --size 16x16 --output " + png.string());
  EXPECT_EQ(volume.code, 2);
  EXPECT_TRUE(says(volume, "cornell-box: is a built-in surface scene")) << volume.err;
  // The compute backend orders every pixel itself: no "mesh order (approximate)" note for it.
  const CliRun compute = run("render --mode interval --quantity color --volume-backend compute --size 16x16 --output " + png.string());
  ASSERT_EQ(compute.code, 0) << compute.err;
  EXPECT_FALSE(says(compute, "mesh order")) << compute.err;
  const CliRun mesh = run("render --mode interval --quantity color --volume-backend mesh --size 16x16 --output " + png.string());
  ASSERT_EQ(mesh.code, 0) << mesh.err;
  EXPECT_TRUE(says(mesh, "draws cells in mesh order (approximate)")) << mesh.err;
}

// Its help promises render's volume options: the camera, --size and --depth-limit are taken
// and checked as render checks them (they were refused as unknown).
TEST(CliRefusals, InfoPlanTakesAndChecksRendersCameraSizeAndDepthLimit) {
  const CliRun ok = run("info --plan --size 64x48 --eye 0,0,5 --near 0.1 --quantity color");
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.out.find("plan (first frame)"), std::string::npos) << ok.out;
  const CliRun up = run("info --plan --up 0,0,0");
  EXPECT_EQ(up.code, 2);
  EXPECT_TRUE(says(up, "up vector is zero")) << up.err;
  const fs::path missing = work_dir() / "no-such-depth.pfm";
  const CliRun depth = run("info --plan --size 8x8 --depth-limit " + missing.string());
  EXPECT_EQ(depth.code, 2);
  EXPECT_TRUE(says(depth, missing.string())) << depth.err;
  const CliRun size = run("info --plan --size 0x48");
  EXPECT_EQ(size.code, 2) << size.err;
}

// `--` ends the options: a file whose name starts with -- opens after it.
TEST(CliRefusals, DoubleDashEndsTheOptions) {
  const fs::path before = fs::current_path();
  fs::current_path(work_dir());
  io::write_tet_mesh_vtu("--odd.vtu", make_box_mesh(glm::dvec3(0.0), glm::dvec3(1.0), 1, [](const glm::dvec3&) { return 1.0; }));
  const CliRun unknown = run("info --odd.vtu");
  const CliRun ended = run("info -- --odd.vtu");
  fs::remove("--odd.vtu");
  fs::current_path(before);
  EXPECT_EQ(unknown.code, 2);
  EXPECT_TRUE(says(unknown, "unknown option")) << unknown.err;
  ASSERT_EQ(ended.code, 0) << ended.err;
  EXPECT_NE(ended.out.find("tetrahedra"), std::string::npos) << ended.out;
}

}  // namespace
}  // namespace prismoid
