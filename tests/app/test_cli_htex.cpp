// End-to-end: `prismoid render SCENE --mode htex` as a user runs it.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/image_io.hpp"
#include "renderer/reference/direct_light.hpp"
#include "scene/surface_generators.hpp"
#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::slurp;
using test::cli::run;
using test::cli::work_dir;

// The Cornell box without shadows: what the CPU direct-light reference computes at each pixel,
// but from texels that are interpolated over about a pixel (tests/surface bounds that per texel
// and per pixel); here, end to end, the image's mean must be the reference's within 2% and
// every pixel finite and covered. (The furnace is not used: its vertex-corner texels lie on
// emissive triangles, where the shared area-light terms are singular; see docs/architecture.md.)
TEST(CliHtex, RendersTheCornellBoxWithStats) {
  const fs::path pfm = work_dir() / "htex_cornell.pfm", stats = work_dir() / "htex_cornell.json";
  const CliRun r = run("render cornell-box --mode htex --no-shadows --size 48x32 --pool-pages 64 --validate --output " + pfm.string() +
                       " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const io::FloatImage img = io::read_pfm(pfm.string());
  ASSERT_EQ(img.width, 48u);
  ASSERT_EQ(img.height, 32u);
  const SurfaceScene scene = make_cornell_box();
  const auto ref = reference::direct_light_image(scene, scene.camera, 48, 32);
  double sum = 0.0, ref_sum = 0.0;
  size_t hits = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    hits += ref.pixels[i].hit;
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(img.pixels[3 * i + size_t(c)]));
      sum += double(img.pixels[3 * i + size_t(c)]);
      ref_sum += ref.pixels[i].radiance[c];
    }
  }
  EXPECT_NEAR(sum / ref_sum, 1.0, 0.02);
  const std::string js = slurp(stats);
  for (const char* key : {"\"mode\": \"htex\"", "\"name\": \"pre-z + marking\"", "\"name\": \"allocation\"", "\"name\": \"shading\"",
                          "\"name\": \"gather\"", "\"hole_pixels\": 0", "\"overflow\": false", "\"pool_pages\": 64",
                          "\"shadows\": false", "\"validation_messages\": 0"})
    EXPECT_NE(js.find(key), std::string::npos) << key << " in " << js;
  EXPECT_NE(js.find("\"covered_pixels\": " + std::to_string(hits) + ","), std::string::npos) << hits << " in " << js;
  EXPECT_EQ(js.find("\"marked_shadels\": 0,"), std::string::npos) << js;
}

// An atlas-based mode (texel, msa) on the Cornell box without shadows, end to end: the same
// whole-image check against the CPU direct light as Htex above (texels interpolated over about a
// pixel; the GPU tests bound them per texel and per pixel), every covered pixel shaded, and the
// stats' keys; returns the shaded texels.
size_t check_atlas_cornell(const std::string& mode, const std::string& options, const std::vector<std::string>& keys, bool check_mean) {
  const SurfaceScene scene = make_cornell_box();
  const auto ref = reference::direct_light_image(scene, scene.camera, 48, 32);
  const fs::path pfm = work_dir() / (mode + "_cornell.pfm"), stats = work_dir() / (mode + "_cornell.json");
  const CliRun r = run("render cornell-box --mode " + mode + " --no-shadows --size 48x32 " + options + " --validate --output " + pfm.string() +
                       " --stats " + stats.string());
  EXPECT_EQ(r.code, 0) << r.err;
  if (r.code != 0) return 0;
  const io::FloatImage img = io::read_pfm(pfm.string());
  EXPECT_EQ(img.width, 48u);
  EXPECT_EQ(img.height, 32u);
  double sum = 0.0, ref_sum = 0.0;
  size_t hits = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    hits += ref.pixels[i].hit;
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(img.pixels[3 * i + size_t(c)]));
      sum += double(img.pixels[3 * i + size_t(c)]);
      ref_sum += ref.pixels[i].radiance[c];
    }
  }
  if (check_mean) {
    EXPECT_NEAR(sum / ref_sum, 1.0, 0.02) << mode << " " << options;
  }
  const std::string js = slurp(stats);
  std::vector<std::string> all = keys;
  for (const char* k : {"\"hole_pixels\": 0", "\"shadows\": false", "\"validation_messages\": 0", "\"name\": \"shading\""}) all.push_back(k);
  all.push_back("\"mode\": \"" + mode + "\"");
  for (const std::string& key : all) EXPECT_NE(js.find(key), std::string::npos) << key << " in " << js;
  EXPECT_NE(js.find("\"covered_pixels\": " + std::to_string(hits) + ","), std::string::npos) << hits << " in " << js;
  const size_t at = js.find("\"shaded_texels\": ");
  EXPECT_NE(at, std::string::npos);
  return at == std::string::npos ? 0 : std::stoull(js.substr(at + 17));
}

// Texel shading; a mip bias of 1 shades fewer texels; bad levels are refused.
TEST(CliTexel, RendersTheCornellBoxWithStats) {
  const std::vector<std::string> keys = {"\"name\": \"pre-z + queue\"", "\"name\": \"gather\""};
  const size_t plain = check_atlas_cornell("texel", "--texel-density 0.1 --mip-bias 0", keys, true);
  const size_t biased = check_atlas_cornell("texel", "--texel-density 0.1 --mip-bias 1", keys, false);
  EXPECT_GT(plain, 0u);
  EXPECT_LT(biased, plain);
  const CliRun bad = run("render cornell-box --mode texel --texel-levels 0 --output " + (work_dir() / "x.pfm").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("level"), std::string::npos) << bad.err;
}

// The meshlet shading atlas, with projected and with conformal charts; a shading budget of a
// quarter shades fewer texels; another mode's options and an unknown chart kind are refused.
TEST(CliMsa, RendersTheCornellBoxWithStats) {
  std::vector<std::string> keys = {"\"name\": \"pre-z + visibility\"", "\"name\": \"block management\"", "\"name\": \"display\"",
                                   "\"clustering\": \"normal-cone\""};
  std::vector<std::string> conformal_keys = keys;
  conformal_keys.push_back("\"charts\": \"conformal\"");
  keys.push_back("\"charts\": \"projection\"");
  EXPECT_GT(check_atlas_cornell("msa", "--msa-charts conformal", conformal_keys, true), 0u);
  const CliRun unknown = run("render cornell-box --mode msa --msa-charts lscm --output " + (work_dir() / "x.pfm").string());
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("--msa-charts"), std::string::npos) << unknown.err;
  const size_t plain = check_atlas_cornell("msa", "", keys, true);
  const size_t budgeted = check_atlas_cornell("msa", "--shading-budget " + std::to_string(std::max<size_t>(1, plain / 4)), keys, false);
  EXPECT_GT(plain, 0u);
  EXPECT_LT(budgeted, plain);
  const CliRun bad = run("render cornell-box --mode msa --texel-levels 2 --output " + (work_dir() / "x.pfm").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--mode texel"), std::string::npos) << bad.err;
  // A stats file that cannot be written: exit 2 naming it, and no partial file left.
  const fs::path stats = work_dir() / "no-such-dir" / "s.json";
  const CliRun unwritable = run("render cornell-box --mode msa --size 16x12 --output " + (work_dir() / "x.pfm").string() + " --stats " + stats.string());
  EXPECT_EQ(unwritable.code, 2);
  EXPECT_NE(unwritable.err.find(stats.string()), std::string::npos) << unwritable.err;
  EXPECT_FALSE(fs::exists(stats.string() + ".partial"));
}

// A lit cube in front of the sky: finite everywhere, and the covered pixels (alpha) are the
// pixels whose centre ray hits the cube, up to the silhouette (pixels a ray grazes).
TEST(CliHtex, CoverageIsTheCubesPixels) {
  const fs::path off = work_dir() / "htex_cube.off", pfm = work_dir() / "htex_cube.pfm", stats = work_dir() / "htex_cube.json";
  SurfaceScene scene;
  scene.name = "cube";
  scene.materials = {SurfaceMaterial{}};
  SceneMesh mesh;
  mesh.name = "cube";
  {
    std::ofstream out(off);
    out << "OFF\n8 12 0\n";
    for (int i = 0; i < 8; ++i) {
      out << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
      mesh.positions.push_back(glm::dvec3(i & 1, (i >> 1) & 1, (i >> 2) & 1));
    }
    for (const std::array<uint32_t, 3> f : std::initializer_list<std::array<uint32_t, 3>>{
             {0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1}, {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}}) {
      out << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
      mesh.triangles.push_back(f);
    }
  }
  scene.meshes.push_back(mesh);
  const CliRun r = run("render " + off.string() + " --mode htex --validate --size 40x30 --eye 2,1.5,3 --target 0.5,0.5,0.5 --up 0,1,0 --fovy 40 "
                       "--near 0.05 --output " + pfm.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const io::FloatImage img = io::read_pfm(pfm.string());
  for (float v : img.pixels) EXPECT_TRUE(std::isfinite(v));
  Camera camera;
  camera.eye = {2, 1.5, 3};
  camera.target = {0.5, 0.5, 0.5};
  camera.up = {0, 1, 0};
  camera.fovy_degrees = 40;
  camera.near_distance = 0.05;
  size_t hits = 0, edge = 0;
  for (int dx = 0; dx < 3; ++dx) {  // the centre ray, and rays 0.02 px away (the silhouette band)
    const double o = dx == 0 ? 0.0 : (dx == 1 ? 0.02 : -0.02);
    const auto ref = reference::direct_light_image(scene, camera, 40, 30, o, o);
    size_t h = 0;
    for (const auto& p : ref.pixels) h += p.hit;
    if (dx == 0) hits = h;
    else edge = std::max(edge, h > hits ? h - hits : hits - h);
  }
  const std::string js = slurp(stats);
  EXPECT_NE(js.find("\"shadows\": true"), std::string::npos) << js;
  EXPECT_NE(js.find("\"validation_messages\": 0"), std::string::npos) << js;
  const auto at = js.find("\"covered_pixels\": ");
  ASSERT_NE(at, std::string::npos) << js;
  const long covered = std::stol(js.substr(at + 18));
  EXPECT_GT(hits, 100u);
  EXPECT_LE(std::abs(covered - long(hits)), long(edge) + 2) << "covered " << covered << ", reference " << hits;
}

TEST(CliHtex, BadInputExitsWithTwoAndNamesTheProblem) {
  const std::string out = (work_dir() / "x.pfm").string();
  const std::pair<std::string, std::string> cases[] = {
      {"render furnace:0.5 --mode htex --pool-pages 0 --output " + out, "--pool-pages"},
      {"render furnace:0.5 --mode htex --pool-pages many --output " + out, "pool-pages"},
      {"render furnace:0.5 --mode htex --pool-pages 4000000000 --output " + out, "--pool-pages"},
      {"render furnace:0.5 --mode htex --texels-per-unit -3 --output " + out, "--texels-per-unit"},
      {"render furnace:0.5 --mode htex --quantity optical-depth --output " + out, "--quantity"},
      {"render /no/such.stl --mode htex --output " + out, "/no/such.stl"},
  };
  for (const auto& [args, needle] : cases) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
  }
}

}  // namespace
}  // namespace prismoid
