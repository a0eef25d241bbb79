// End-to-end: the surface modes of the mode table through the command line as a user runs it:
// every mode renders by its name, `info --plan` and `render --stats` give the surface frame's
// plan with its reasons, and render's help lists the table.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "io/image_io.hpp"
#include "renderer/surface/surface_backend.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::slurp;
using test::cli::run;
using test::cli::work_dir;

TEST(CliSurface, RenderHelpListsEverySurfaceModeOfTheTable) {
  const CliRun r = run("render --help");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const surface::SurfaceMode& m : surface::surface_mode_table())
    EXPECT_NE(r.out.find("  " + std::string(m.name) + ": " + std::string(m.summary) + "\n"), std::string::npos) << m.name;
  // Each backend's options, from its table line: the option with its value's form, and its help
  // (wrapped: its first words).
  for (const surface::SurfaceMode& m : surface::surface_mode_table())
    if (m.gpu())
      for (const surface::SurfaceOption& o : m.backend->options) {
        const std::string help(o.help);
        const std::string option = "    --" + std::string(o.name) + (o.flag ? "" : " " + std::string(o.value));
        const size_t at = r.out.find(option);
        ASSERT_NE(at, std::string::npos) << o.name;
        EXPECT_TRUE(std::isspace(static_cast<unsigned char>(r.out[at + option.size()]))) << o.name;
        EXPECT_NE(r.out.find(help.substr(0, help.find(' ', 24))), std::string::npos) << o.name << "'s help";
      }
  EXPECT_EQ(run("help render").out, r.out);
}

// The planner's surface frame without a GPU: cornell-box's default mode (the table's first),
// a GI mode, and a surface file, which has no lights and so gets the default key light (which
// casts shadows) and the sky (which GI bounces).
TEST(CliSurface, InfoPlanGivesTheSurfaceFramesPassesWithReasons) {
  CliRun r = run("info cornell-box --plan");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string first(surface::surface_mode_table().front().name);
  EXPECT_NE(r.out.find("cornell-box: 32 triangles, 0 point and 0 directional lights, 2 emissive triangles, no sky; mode " + first + "\n"),
            std::string::npos) << r.out;
  for (const std::string line : {"\n  depth pre-pass (GPU): ", "\n  forward shading (GPU): ",
                                 "\n  shadow rays (GPU, within the pass above): 2 emissive triangles cast shadows: ",
                                 "\n  allocation: forward shades per pixel", "\n  gi: no indirect light asked for (mode forward)\n",
                                 "\n  display: forward shading writes the image itself\n"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << " in\n" << r.out;

  r = run("info cornell-box --plan --mode htex-gi-unbiased");
  ASSERT_EQ(r.code, 0) << r.err;
  size_t at = 0;
  for (const std::string line : {"\n  pre-z + marking (GPU): ", "\n  allocation (GPU): ", "\n  shading (GPU): ", "\n  shadow rays (GPU, within",
                                 "\n  gi samples (GPU): one-bounce indirect light asked for (mode htex-gi-unbiased: ReSTIR GI, unbiased), "
                                 "bouncing the light of 2 emissive triangles off 32 triangles: ",
                                 "\n  gi initial+temporal (GPU): ", "\n  gi spatial (GPU): ", "\n  gather (GPU): ", "\nskipped: none\n"}) {
    const size_t found = r.out.find(line, at);
    EXPECT_NE(found, std::string::npos) << line << " in order in\n" << r.out;
    if (found != std::string::npos) at = found;
  }

  const fs::path off = work_dir() / "plan_cube.off";
  {
    std::ofstream out(off);
    out << "OFF\n8 12 0\n";
    for (int i = 0; i < 8; ++i) out << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    for (const char* f : {"0 1 3", "0 3 2", "4 6 7", "4 7 5", "0 4 5", "0 5 1", "2 3 7", "2 7 6", "0 2 6", "0 6 4", "1 5 7", "1 7 3"})
      out << "3 " << f << "\n";
  }
  r = run("info " + off.string() + " --plan --mode texel");
  ASSERT_EQ(r.code, 0) << r.err;
  for (const std::string line : {"12 triangles, 0 point and 1 directional lights, 0 emissive triangles, a sky (no lights of its own",
                                 "\n  pre-z + queue (GPU): ", "\n  shadow rays (GPU, within the pass above): 1 directional light casts shadows: ",
                                 "\n  allocation: the texel atlas is static", "\n  gi: no indirect light asked for (mode texel)\n"})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << " in\n" << r.out;

  // The CPU mode has no GPU passes; a volume's plan is unchanged.
  r = run("info cornell-box --plan --mode path-reference");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("on the CPU (no GPU passes)"), std::string::npos) << r.out;
  r = run("info field:blobs --plan --quantity color");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("\n  surface-shading: no surfaces in the scene\n"), std::string::npos) << r.out;
}

// The stats of a surface render carry its plan as the volume modes' do: the planned passes
// (the shadow rays within the shading pass) and the skipped ones with why; they are the passes
// that ran.
TEST(CliSurface, RenderStatsListThePlannedAndSkippedPasses) {
  const fs::path pfm = work_dir() / "plan.pfm", stats = work_dir() / "plan.json";
  CliRun r = run("render cornell-box --mode forward --shadows off --size 16x12 --validate --output " + pfm.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  std::string js = slurp(stats);
  for (const std::string key : {"\"plan\": [", "{\"name\": \"depth pre-pass\", \"kind\": \"gpu\", \"reason\": \"positions only",
                                "{\"name\": \"forward shading\", \"kind\": \"gpu\", \"reason\": ", "\"skipped\": [",
                                "{\"pass\": \"shadow rays\", \"reason\": \"shadows are off\"}",
                                "{\"pass\": \"gi\", \"reason\": \"no indirect light asked for (mode forward)\"}", "\"shadows\": false"})
    EXPECT_NE(js.find(key), std::string::npos) << key << " in " << js;

  r = run("render cornell-box --mode msa --size 16x12 --validate --output " + pfm.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  js = slurp(stats);
  for (const std::string key : {"{\"name\": \"pre-z + visibility\", \"kind\": \"gpu\"", "{\"name\": \"block management\", \"kind\": \"gpu\"",
                                "{\"name\": \"shading\", \"kind\": \"gpu\"", "{\"name\": \"shadow rays\", \"kind\": \"within\", \"reason\": \"2 emissive",
                                "{\"name\": \"display\", \"kind\": \"gpu\"", "\"shadows\": true", "\"validation_messages\": 0"})
    EXPECT_NE(js.find(key), std::string::npos) << key << " in " << js;
}

// One spelling of the shadows setting for every surface mode: --shadows off leaves the shadow
// rays out of each backend's plan (their default is on here: lavapipe traces rays and the box's
// light casts shadows, as RenderStatsListThePlannedAndSkippedPasses checks for msa). The
// texture-space modes' old --no-shadows still works, with a note naming the new spelling; both at
// once are refused.
TEST(CliSurface, EveryGpuModeTakesShadowsOnOrOff) {
  const fs::path pfm = work_dir() / "shadows.pfm", stats = work_dir() / "shadows.json";
  std::string backends;
  for (const surface::SurfaceMode& m : surface::surface_mode_table()) {
    if (!m.gpu() || m.gi != frame::SurfaceGi::None) continue;
    std::string args = "render cornell-box --mode " + std::string(m.name) + " --shadows off --size 16x12 --validate --output " +
                       pfm.string() + " --stats " + stats.string();
    if (m.backend == surface::find_surface_mode("htex")->backend) args += " --pool-pages 16 --texels-per-unit 0.05";
    const CliRun r = run(args);
    ASSERT_EQ(r.code, 0) << m.name << ": " << r.err;
    const std::string js = slurp(stats);
    EXPECT_NE(js.find("{\"pass\": \"shadow rays\", \"reason\": \"shadows are off\"}"), std::string::npos) << m.name << ": " << js;
    EXPECT_NE(js.find("\"shadows\": false"), std::string::npos) << m.name << ": " << js;
    backends += std::string(m.name) + " ";
  }
  EXPECT_NE(backends.find("forward"), std::string::npos) << backends;
  EXPECT_NE(backends.find("msa"), std::string::npos) << backends;

  CliRun r = run("render cornell-box --mode msa --no-shadows --size 16x12 --output " + pfm.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("note: --no-shadows is spelled --shadows off now"), std::string::npos) << r.err;
  EXPECT_NE(slurp(stats).find("{\"pass\": \"shadow rays\", \"reason\": \"shadows are off\"}"), std::string::npos);
  r = run("render cornell-box --mode forward --no-shadows --size 16x12 --output " + pfm.string());
  EXPECT_EQ(r.code, 0) << "forward understands the old spelling too: " << r.err;
  r = run("render cornell-box --mode msa --no-shadows --shadows on --size 16x12 --output " + pfm.string());
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("--no-shadows: is the old spelling of --shadows off"), std::string::npos) << r.err;
}

// Every GPU mode of the table renders by its own name (the GI modes too, which render's --gi
// names as well); an unknown mode is not a surface mode.
TEST(CliSurface, EveryGpuModeOfTheTableRendersByItsName) {
  const fs::path pfm = work_dir() / "mode.pfm", stats = work_dir() / "mode.json";
  for (const surface::SurfaceMode& m : surface::surface_mode_table()) {
    if (!m.gpu()) continue;
    std::string args = "render cornell-box --mode " + std::string(m.name) + " --size 16x12 --validate --output " + pfm.string() + " --stats " +
                       stats.string();
    if (m.backend == surface::find_surface_mode("htex")->backend) args += " --pool-pages 16 --texels-per-unit 0.05";
    if (m.gi != frame::SurfaceGi::None) args += " --gi-frames 2";
    const CliRun r = run(args);
    ASSERT_EQ(r.code, 0) << m.name << ": " << r.err;
    const io::FloatImage img = io::read_pfm(pfm.string());
    ASSERT_EQ(img.width, 16u) << m.name;
    for (float v : img.pixels) ASSERT_TRUE(std::isfinite(v)) << m.name;
    const std::string js = slurp(stats);
    EXPECT_NE(js.find("\"mode\": \"" + std::string(m.name) + "\""), std::string::npos) << js;
    EXPECT_NE(js.find("\"validation_messages\": 0"), std::string::npos) << js;
    if (m.gi != frame::SurfaceGi::None) {
      EXPECT_NE(js.find("\"gi\": \"" + std::string(frame::surface_gi_name(m.gi)) + "\""), std::string::npos) << js;
      EXPECT_NE(js.find("\"gi_frames\": 2"), std::string::npos) << js;
      EXPECT_NE(js.find("{\"name\": \"gi spatial\", \"kind\": \"gpu\""), std::string::npos) << js;
    }
  }
}

// The options and scene names the per-frame atlases brought (and the refinement of large
// triangles), given carelessly: each refused with exit 2 and a message naming the option or the
// name, and no image written.
// Each `render ARGS` is refused (exit 2) with its message on stderr, writing no `out`.
template <size_t N>
void expect_each_refused(const std::pair<std::string, std::string> (&cases)[N], const fs::path& out) {
  for (const auto& [args, message] : cases) {
    fs::remove(out);
    const CliRun r = run("render " + args + " --size 16x12 --output " + out.string());
    EXPECT_EQ(r.code, 2) << args << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << ": " << r.err;
    EXPECT_FALSE(fs::exists(out)) << args;
  }
}

TEST(CliSurface, PerFrameAtlasOptionsGivenBadlyAreRefusedByName) {
  const fs::path out = work_dir() / "refused.pfm";
  const std::pair<std::string, std::string> cases[] = {
      {"cornell-box --mode fastatlas --atlas 3000", "--atlas: the atlas side must be a power of two"},
      {"cornell-box --mode fastatlas --atlas 32768", "--atlas: the atlas side must be a power of two"},
      {"cornell-box --mode fastatlas --atlas abc", "--atlas"},
      {"cornell-box --mode fastatlas --shading-scale nan", "--shading-scale"},
      {"cornell-box --mode fastatlas --shading-scale -1", "--shading-scale"},
      {"cornell-box --mode fastatlas --shading-scale 5", "--shading-scale: at most 4"},
      {"cornell-box --mode msa --msa-charts sideways", "--msa-charts"},
      {"cornell-box --mode msa --max-triangle-pixels 0", "--max-triangle-pixels: the largest extent must be"},
      {"cornell-box --mode msa --max-triangle-pixels nan", "--max-triangle-pixels"},
      {"cornell-box --mode msa --max-triangle-pixels 1e-9", "--max-triangle-pixels: 0.000000 pixels would split cornell-box into more than"},
      {"cornell-box --mode path-reference --max-triangle-pixels -2", "--max-triangle-pixels"},
      {"tiled:0:bunny.off --mode forward", "tiled:0:bunny.off: the copies a side must be a whole number from 1 to 64"},
      {"tiled:2 --mode forward", "tiled:2: a tiled scene is tiled:N:FILE"},
      {"tiled:2:no-such-file.off --mode forward", "no-such-file.off"},
  };
  expect_each_refused(cases, out);
}

// One surface verb parses every surface mode's options: each is refused, by name, for the modes
// that do not take it, naming one that does (the path tracer's for the GPU modes and back).
TEST(CliSurface, EachModesOptionsAreRefusedForTheOthersNamingAModeThatTakesThem) {
  const fs::path out = work_dir() / "refused-option.pfm";
  const std::pair<std::string, std::string> cases[] = {
      {"cornell-box --mode forward --spp 4", "--spp: is an option of --mode path-reference"},
      {"cornell-box --mode htex --variance v.pfm", "--variance: is an option of --mode path-reference"},
      {"cornell-box --mode path-reference --frames 2", "--frames: is an option of --mode forward"},
      {"cornell-box --mode path-reference --shadows off", "--shadows: is an option of --mode forward"},
      {"cornell-box --mode path-reference --no-shadows", "--no-shadows: is an option of --mode forward"},
      {"cornell-box --mode path-reference --reference-error", "--mode path-reference is the reference itself"},
  };
  expect_each_refused(cases, out);
}

}  // namespace
}  // namespace prismoid
