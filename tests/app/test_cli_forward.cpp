// End-to-end: `prismoid render SCENE --mode forward` as a user runs it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include "app/common/cli_args.hpp"
#include "app/common/surface_args.hpp"
#include "io/image_io.hpp"
#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/camera.hpp"
#include "scene/surface_generators.hpp"
#include "support/cli_run.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

using test::CliRun;
using test::slurp;
using test::cli::run;
using test::cli::work_dir;

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
  const CliRun r = run("render cornell-box --mode forward --shadows off --size 32x32 --supersample 2 --output " + pfm.string());
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

// A surface file has no lights: the default key light (it casts shadows) and sky light it, and the sky is seen
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
  EXPECT_NE(r.out.find("default key light (it casts shadows) and sky"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string());
  for (float v : img.pixels) EXPECT_GT(v, 0.0f);
}

// --shadows on: the ray-traced pass, whose image is the CPU twin with shadows: every pixel but
// those next to a silhouette (where the rasterizer may keep either surface) within 1e-4 of the
// peak, and the shadows make a difference (the unshadowed image differs in many pixels).
TEST(CliForward, ShadowsOnMatchesTheShadowedTwin) {
  const fs::path pfm = work_dir() / "cornell_shadows.pfm", stats = work_dir() / "cornell_shadows.json";
  const CliRun r = run("render cornell-box --mode forward --shadows on --size 64x48 --validate --output " + pfm.string() + " --stats " +
                       stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("ray-traced shadows"), std::string::npos) << r.out;
  const io::FloatImage img = io::read_pfm(pfm.string());
  const SurfaceScene scene = make_cornell_box();
  reference::DirectLightOptions options;
  options.shadows = true;
  const auto twin = reference::direct_light_image(scene, scene.camera, 64, 48, 0.0, 0.0, options);
  const auto plain = reference::direct_light_image(scene, scene.camera, 64, 48);
  double peak = 0.0;
  for (const auto& p : twin.pixels) peak = std::max({peak, p.radiance.x, p.radiance.y, p.radiance.z});
  size_t off = 0, edge = 0, shadowed = 0, covered = 0;
  for (uint32_t y = 0; y < 48; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      const size_t i = size_t(y) * 64 + x;
      covered += twin.pixels[i].hit;
      bool near_edge = false;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int nx = int(x) + dx, ny = int(y) + dy;
          if (nx < 0 || ny < 0 || nx >= 64 || ny >= 48) continue;
          const auto& n = twin.pixels[size_t(ny) * 64 + size_t(nx)];
          near_edge = near_edge || n.hit != twin.pixels[i].hit || n.mesh != twin.pixels[i].mesh;
        }
      double error = 0.0, change = 0.0;
      for (int c = 0; c < 3; ++c) {
        error = std::max(error, std::abs(double(img.pixels[i * 3 + c]) - twin.pixels[i].radiance[c]));
        change = std::max(change, std::abs(plain.pixels[i].radiance[c] - twin.pixels[i].radiance[c]));
      }
      if (near_edge || twin.pixels[i].shadow_ambiguous) {
        ++edge;
        continue;
      }
      off += error > 1e-4 * peak;
      shadowed += change > 2e-4 * peak;  // twice the tolerance: an unshadowed image fails there
    }
  EXPECT_EQ(off, 0u) << edge << " pixels near an edge left out";
  EXPECT_LT(edge, size_t(64 * 48 / 2));
  EXPECT_GT(shadowed, 50u) << "pixels the shadows change";
  std::printf("[ cli shadows ] %zu pixels compared, %zu near an edge, %zu changed by shadows\n", size_t(64 * 48) - edge, edge, shadowed);
  const std::string js = slurp(stats);
  for (const std::string& key : {std::string("\"shadows\": true"), std::string("\"name\": \"depth pre-pass\""),
                                std::string("\"name\": \"forward shading\""), std::string("\"validation_messages\": 0"),
                                "\"shading_invocations\": " + std::to_string(covered)})
    EXPECT_NE(js.find(key), std::string::npos) << key << " in " << js;
}

// On a surface file (the default key light, which casts shadows, and sky) --shadows on works
// and, the cube being convex, casts no shadow on itself: the image of --shadows off (to
// the raster path's sub-pixel snapping, which moves the shaded point by 2^-8 pixel).
TEST(CliForward, ShadowsOnASurfaceFile) {
  const fs::path off = work_dir() / "shadow_cube.off", on_pfm = work_dir() / "cube_on.pfm", off_pfm = work_dir() / "cube_off.pfm";
  {
    std::ofstream out(off);
    out << "OFF\n8 12 0\n";
    for (int i = 0; i < 8; ++i) out << (i & 1) << " " << ((i >> 1) & 1) << " " << ((i >> 2) & 1) << "\n";
    for (const char* f : {"0 1 3", "0 3 2", "4 6 7", "4 7 5", "0 4 5", "0 5 1", "2 3 7", "2 7 6", "0 2 6", "0 6 4", "1 5 7", "1 7 3"})
      out << "3 " << f << "\n";
  }
  const CliRun on = run("render " + off.string() + " --mode forward --shadows on --size 20x20 --eye 2,1.5,3 --output " + on_pfm.string());
  ASSERT_EQ(on.code, 0) << on.err;
  EXPECT_NE(on.out.find("ray-traced shadows"), std::string::npos) << on.out;
  const CliRun plain = run("render " + off.string() + " --mode forward --shadows off --size 20x20 --eye 2,1.5,3 --output " + off_pfm.string());
  ASSERT_EQ(plain.code, 0) << plain.err;
  EXPECT_NE(plain.out.find("without shadows"), std::string::npos) << plain.out;
  const io::FloatImage a = io::read_pfm(on_pfm.string()), b = io::read_pfm(off_pfm.string());
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    EXPECT_GT(a.pixels[i], 0.0f);
    EXPECT_NEAR(a.pixels[i], b.pixels[i], 1e-3 * std::max(1.0, double(b.pixels[i]))) << i;  // sub-pixel snapping of the raster path
  }
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
      {"render cornell-box --mode forward --shadows maybe --output " + out, "--shadows"},
  };
  for (const auto& [args, needle] : cases) {
    const CliRun r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << "\n" << r.err;
  }
}

std::vector<std::string> words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// A unit square in z = 0 as VTK XML polydata: a vertex cell first (so the polygon's cell data
// sit after it), then the square as one quad (split into two triangles on reading); point
// array "x" = the point's x, cell array "id" a 3-vector per cell.
fs::path write_square_vtp() {
  const fs::path vtp = work_dir() / "square.vtp";
  std::ofstream(vtp) << R"(<?xml version="1.0"?>
<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">
<PolyData><Piece NumberOfPoints="4" NumberOfVerts="1" NumberOfLines="0" NumberOfStrips="0" NumberOfPolys="1">
<PointData><DataArray type="Float64" Name="x" format="ascii">0 1 1 0</DataArray></PointData>
<CellData><DataArray type="Float64" Name="id" NumberOfComponents="3" format="ascii">9 9 9 0.25 0.5 2</DataArray></CellData>
<Points><DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 1 1 0 0 1 0</DataArray></Points>
<Verts><DataArray type="Int64" Name="connectivity" format="ascii">0</DataArray><DataArray type="Int64" Name="offsets" format="ascii">1</DataArray></Verts>
<Polys><DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3</DataArray><DataArray type="Int64" Name="offsets" format="ascii">4</DataArray></Polys>
</Piece></PolyData></VTKFile>
)";
  return vtp;
}

// Colour by a data array through the transfer function, as the CPU reference sees it: the
// scene the CLI builds has the transfer function's colours (grayscale: the array's range onto
// black..white, linear), and the GPU image matches the CPU direct light of that scene away from
// the square's edges (relative 1e-4: float shading of a few terms). A point array's colours are
// interpolated across the quad's two triangles; a cell array colours the quad's two triangles
// with the quad's tuple.
TEST(CliForward, ColoursBySurfaceArraysThroughTheTransferFunction) {
  const fs::path vtp = write_square_vtp(), pfm = work_dir() / "x.pfm";
  const uint32_t w = 48, h = 36;
  const std::string camera = " --eye 0.5,0.5,2 --target 0.5,0.5,0 --up 0,1,0 --fovy 40";
  for (const std::string coloring : {"--array x --tf grayscale", "--array id --component y --tf grayscale --tf-range 0,1"}) {
    const CliRun r = run("render " + vtp.string() + " --mode forward --validate " + coloring + " --size " + std::to_string(w) + "x" +
                         std::to_string(h) + camera + " --output " + pfm.string());
    ASSERT_EQ(r.code, 0) << r.err;
    const io::FloatImage img = io::read_pfm(pfm.string());
    app::ParsedArgs a = app::parse(words(vtp.string() + " " + coloring + camera), 0,
                                   app::with_surface_color(app::with_camera({})), {});
    const SurfaceScene raw = app::surface_scene_from(a, "forward");
    const Camera cam = app::surface_camera(a, raw);
    const SurfaceScene scene = with_default_lighting(raw, cam);
    const SceneMesh& mesh = scene.meshes.at(0);
    if (coloring.find("--array x") != std::string::npos) {
      ASSERT_EQ(mesh.color_binding, ColorBinding::PerVertex);
      for (size_t v = 0; v < mesh.positions.size(); ++v)
        EXPECT_NEAR(mesh.colors[v].g, mesh.positions[v].x, 1e-12) << "vertex " << v;  // x in [0, 1] onto grey x
    } else {
      ASSERT_EQ(mesh.color_binding, ColorBinding::PerTriangle);
      ASSERT_EQ(mesh.colors.size(), 2u);
      for (const auto& c : mesh.colors) EXPECT_NEAR(c.r, 0.5, 1e-12);  // the quad's y = 0.5, not the vertex cell's 9
    }
    const reference::DirectLightImage ref = reference::direct_light_image(scene, cam, w, h);
    const std::vector<float> ref_rgb = ref.rgb();
    size_t compared = 0;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const size_t p = size_t(y) * w + x;
        const auto& hit = ref.pixels[p];
        const glm::dvec3 point = cam.eye + hit.t * reference::ray_direction(cam, w, h, x + 0.5, y + 0.5);
        if (!hit.hit || std::min({point.x, point.y, 1.0 - point.x, 1.0 - point.y}) < 0.03) continue;
        // io::read_pfm gives row 0 at the top (the file's bottom-up rows are turned). This read
        // rows upside down until the default light stopped being a headlight: the square's
        // image was symmetric top to bottom under it, so the error could not show.
        const size_t row = size_t(y) * w + x;
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(double(img.pixels[3 * row + c]), double(ref_rgb[3 * p + c]), 1e-4 * std::abs(double(ref_rgb[3 * p + c])) + 1e-6) << coloring << " " << x << "," << y;
        ++compared;
      }
    EXPECT_GT(compared, w * h / 4) << coloring;
  }

  // An unknown array names the file and lists what it has; --component past the last fails too.
  CliRun r = run("render " + vtp.string() + " --mode forward --array pressure --output " + pfm.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("has no array 'pressure' (arrays: x (point), id (cell))"), std::string::npos) << r.err;
  r = run("render " + vtp.string() + " --mode forward --array x --component 2 --output " + pfm.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("has 1 component(s)"), std::string::npos) << r.err;
  r = run("render cornell-box --mode forward --array x --output " + pfm.string());
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("no data arrays"), std::string::npos) << r.err;
}

// A camera placed by hand (--eye, --target, no --near) sees the whole floor under it: every pixel
// whose ray meets the 8 x 8 floor is covered, as the ray-plane intersection says (pixels within a
// pixel of the floor's far edge aside). The default framing's near plane once cut away the near
// half (app/common/cli_args.cpp: near_plane_for).
TEST(CliForward, AnEyePlacedByHandSeesTheWholeFloorUnderIt) {
  const fs::path off = work_dir() / "wide_floor.off", png = work_dir() / "wide_floor.png", stats = work_dir() / "wide_floor.json";
  std::ofstream(off) << "OFF\n4 2 0\n-4 -1.05 -4\n4 -1.05 -4\n4 -1.05 4\n-4 -1.05 4\n3 0 3 2\n3 0 2 1\n";
  const uint32_t w = 80, h = 60;
  const CliRun r = run("render " + off.string() + " --mode forward --eye 2.6,1.7,3.6 --target 0,-0.2,0 --size " + std::to_string(w) + "x" +
                       std::to_string(h) + " --output " + png.string() + " --stats " + stats.string());
  ASSERT_EQ(r.code, 0) << r.err;
  Camera c;
  c.eye = {2.6, 1.7, 3.6};
  c.target = {0.0, -0.2, 0.0};
  c.fovy_degrees = 40.0;
  auto meets = [&](double px, double py) {
    const glm::dvec3 d = reference::ray_direction(c, w, h, px, py);
    const double t = (-1.05 - c.eye.y) / d.y;
    const glm::dvec3 p = c.eye + t * d;
    return t > 0.0 && std::abs(p.x) <= 4.0 && std::abs(p.z) <= 4.0;
  };
  size_t sure = 0, edge = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const bool centre = meets(x + 0.5, y + 0.5);
      bool differs = false;
      for (const auto& [dx, dy] : {std::pair{1.0, 0.0}, {-1.0, 0.0}, {0.0, 1.0}, {0.0, -1.0}}) differs |= meets(x + 0.5 + dx, y + 0.5 + dy) != centre;
      (differs ? edge : sure) += differs || centre;
    }
  const std::string js = slurp(stats);
  const size_t at = js.find("\"covered_pixels\": ");
  ASSERT_NE(at, std::string::npos) << js;
  const size_t covered = std::stoul(js.substr(at + 18));
  EXPECT_GE(covered, sure) << "pixels whose ray meets the floor are not drawn";
  EXPECT_LE(covered, sure + edge);
  EXPECT_GT(sure, size_t(w) * h / 2);
}

}  // namespace
}  // namespace prismoid
