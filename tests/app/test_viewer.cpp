// The window under a real X server (Xvfb on lavapipe in CI), driven by scripts the way a person
// would drive it: it opens, presents, survives resizing and minimizing, draws its panels,
// switches modes and transfer functions, takes screenshots and renders, and closes, with the
// validation layer silent. Assertions are on the screenshots' pixels and the reported stats.
#include <gtest/gtest.h>

#include <stb/stb_image.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <sstream>
#include <chrono>

#include "app/cli.hpp"
#include "app/common/frame_stats_writer.hpp"
#include "app/viewer/camera_controller.hpp"
#include "app/viewer/camera_line.hpp"
#include "app/viewer/interactive_scale.hpp"
#include "app/common/dataset_loader.hpp"
#include "app/viewer/view_state.hpp"
#include "app/viewer/viewer.hpp"
#include "io/vtk_tet_io.hpp"
#include "io/image_io.hpp"
#include "renderer/metrics/image_error.hpp"
#include "scene/generators.hpp"
#include "support/box_view.hpp"
#include "support/cube_surface.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

struct Png {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
  const unsigned char* at(int x, int y) const { return &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3]; }
};

Png read_png(const std::string& path) {
  Png png;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &png.width, &png.height, &channels, 3);
  if (!data) throw std::runtime_error("cannot read " + path);
  png.rgb.assign(data, data + size_t(png.width) * size_t(png.height) * 3);
  stbi_image_free(data);
  return png;
}

fs::path out_dir(const std::string& test) {
  const fs::path dir = fs::temp_directory_path() / ("prismoid-viewer-" + test);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

app::ViewerOptions window_options(uint32_t width, uint32_t height, const std::string& script) {
  app::ViewerOptions options;
  options.width = width;
  options.height = height;
  options.validation = true;
  options.print_timings = false;
  options.script = app::parse_script(script, "test script");
  options.max_frames = 2000;  // a safety net: every script closes the window long before
  // Full resolution in every frame, whatever this machine's speed, so that the scripts'
  // screenshots are the data's (the test of moving frames sets its own target).
  options.moving_target_ms = 1e12;
  return options;
}

#define REQUIRE_DISPLAY() \
  ASSERT_TRUE(app::display_available()) << "this test needs a display: run it through scripts/test.sh, which starts Xvfb"

TEST(Viewer, PresentsResizesMinimizesAndClosesWithoutValidationMessages) {
  REQUIRE_DISPLAY();
  app::ViewerOptions options = window_options(320, 240,
                                              "frame 4\nresize 400 300\nframe 10\niconify\nframe 16\nrestore\n"
                                              "frame 22\nresize 200 360\nframe 30\nclose\n");
  const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
  // Frames 0..30 run (the close request is seen at the top of frame 31). Without a window
  // manager (plain Xvfb) iconify is a no-op and every frame presents; with one, the
  // minimized frames are skipped instead. Either way each frame is accounted for once.
  EXPECT_GE(report.frames_presented, 15u);
  EXPECT_EQ(report.frames_presented + report.frames_skipped_minimized, 31u);
  EXPECT_GE(report.swapchain_recreations, 2u);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_TRUE(report.messages.empty());
}

// Zooming far out, with the wheel or a right drag, keeps the window drawing: the camera stops
// where the data is under a pixel (it once went on to 1e32 away, and the frame's float limits
// ended the window with exit 2).
TEST(Viewer, ZoomingFarOutKeepsTheWindowOpen) {
  REQUIRE_DISPLAY();
  app::ViewerOptions options = window_options(160, 120, "frame 1\nzoom -700\nframe 3\ndrag 0 30000 right\nframe 5\nclose\n");
  const TetMesh mesh = make_default_volume();
  const app::ViewerReport report = app::run_viewer(mesh, options);
  EXPECT_EQ(report.frames_presented, 6u);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_TRUE(report.messages.empty()) << report.messages.front();
  EXPECT_TRUE(report.error_popups.empty()) << report.error_popups.front();
  const Bounds b = bounds_of(mesh);
  EXPECT_LE(glm::distance(report.camera.eye, b.center()), app::CameraController::kFarthest * b.radius() * (1.0 + 1e-9));
}

// While the camera moves, a frame slower than the target makes the next ones coarser, one level
// at a time, down to the coarser of the data's two proxies; when it stops the data itself is drawn at full
// resolution. The target is set unreachable (a microsecond), so the steps do not depend on this
// machine's speed; the validation layer stays silent through every size and the proxy.
TEST(Viewer, AMovingCameraStepsDownToTheProxyAndAStillOneGetsFullResolution) {
  REQUIRE_DISPLAY();
  std::string script;
  for (int f = 2; f < 22; ++f) script += "frame " + std::to_string(f) + "\nrotate 5 0\n";
  script += "frame 25\nclose\n";
  app::ViewerOptions options = window_options(160, 120, script);
  options.moving_target_ms = 1e-3;
  options.settings.resolve.quantity = volume::Quantity::Color;
  options.settings.resolve.transfer.range_hi = 6.0;
  options.settings.ordering = frame::Ordering::GpuSort;
  // 28^3 cubes, 131,712 cells: more than four times the proxy's 24,576, so the proxy is offered.
  const TetMesh mesh = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 28, [](const glm::dvec3& p) { return 2.0 * std::exp(-glm::dot(p, p)); });
  const app::ViewerReport report = app::run_viewer(mesh, options);
  EXPECT_EQ(report.validation_messages, 0u);
  ASSERT_FALSE(report.moving_frames.empty());
  uint32_t previous = 0;
  for (const auto& [ms, level] : report.moving_frames) {
    EXPECT_GE(level, previous);  // never finer while every frame misses the target
    EXPECT_LE(level, previous + 1);  // one level at a time
    previous = level;
  }
  EXPECT_EQ(report.moving_frames.back().second, app::InteractiveScale::kCoarsestProxy);
  EXPECT_FALSE(report.still_frames_ms.empty());  // drawn after the motion, at full resolution
  EXPECT_EQ(report.last_frame.resolution_level, 0u);
  EXPECT_EQ(report.last_frame.cells, mesh.tets.size());
  // Both proxies were made beside the frames, on the present thread, while the loop read input;
  // no frame stopped to make one.
  EXPECT_EQ(report.proxies_made_beside_frames, 2u);
  EXPECT_EQ(report.proxies_made_in_frames, 0u);
}

// The window draws what render draws: emission-absorption in exact order (a CPU order each
// frame, copied to the GPU while no frame is in flight) and in GPU-sorted order, resizing
// mid-way (new targets), with the validation layer silent.
TEST(Viewer, ColourInEachOrderingPresentsWithoutValidationMessages) {
  REQUIRE_DISPLAY();
  for (const auto ordering : {frame::Ordering::Exact, frame::Ordering::GpuSort}) {
    app::ViewerOptions options = window_options(160, 120, "frame 3\nresize 200 150\nframe 8\nclose\n");
    options.settings.resolve.quantity = volume::Quantity::Color;
    options.settings.resolve.transfer.range_hi = 6.0;
    options.settings.ordering = ordering;
    const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
    EXPECT_GE(report.frames_presented, 5u);
    EXPECT_EQ(report.validation_messages, 0u);
    // The last frame's camera was still, so it drew with the order an earlier frame made.
    const std::string expected = ordering == frame::Ordering::Exact ? "upload-order" : "sort";
    const frame::FramePlan& plan = report.last_frame.report().plan;
    EXPECT_TRUE(plan.reuses_order);
    EXPECT_TRUE(std::any_of(plan.skipped.begin(), plan.skipped.end(), [&](const frame::SkippedPass& p) {
      return p.name == expected && p.reason.rfind("order reused: camera still", 0) == 0;
    })) << "the frame plan neither runs nor reuses " << expected;
  }
}

bool has_pass(const app::ViewerReport& r, const std::string& name) {
  const auto& p = r.last_frame.frame.passes;
  return std::any_of(p.begin(), p.end(), [&](const vk::PassTiming& t) { return t.name == name; });
}

// Pixels where the volume clearly shows over the white background (below 90% in some channel).
std::vector<size_t> volume_pixels(const Png& png) {
  std::vector<size_t> v;
  for (size_t i = 0; i < size_t(png.width) * size_t(png.height); ++i)
    if (png.rgb[3 * i] < 230 || png.rgb[3 * i + 1] < 230 || png.rgb[3 * i + 2] < 230) v.push_back(i);
  return v;
}

// One session: mode and transfer-function changes through the script, screenshots with and
// without the panels, a render at the window's size, and the camera line.
TEST(Viewer, ScriptedSessionChangesWhatIsDrawnAndReportsIt) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("session");
  std::ostringstream script;
  script << "frame 1\nui off\nmode interval-sorted\nquantity color\ndensity-scale 8\ntf cool-to-warm\ntf-range data\n"
         << "drag 40 -20 left\ndrag 6 3 middle\ndrag 0 -20 right\n"
         << "frame 3\nscreenshot " << (dir / "cool.png").string() << "\n"
         << "frame 4\ntf black-body\n"
         << "frame 6\nscreenshot " << (dir / "black-body.png").string() << "\n"
         << "frame 7\nui on\n"
         << "frame 9\nscreenshot " << (dir / "with-ui.png").string() << "\n"
         << "render 480 360 " << (dir / "render.png").string() << "\n"
         << "print-camera\n"
         << "tf-export " << (dir / "tf.json").string() << "\n"
         << "frame 11\nclose\n";
  app::ViewerOptions options = window_options(480, 360, script.str());
  const TetMesh mesh = make_default_volume();
  const app::ViewerReport report = app::run_viewer(mesh, options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_TRUE(report.messages.empty()) << report.messages.front();
  ASSERT_EQ(report.files_written.size(), 5u);

  // The transfer function changes the volume's colours: mean absolute difference over the
  // volume's pixels. Cool-to-warm and black-body differ by far more than 8-bit rounding
  // (their colours at the same scalar differ by tenths of full scale over most of the range).
  const Png cool = read_png((dir / "cool.png").string()), black = read_png((dir / "black-body.png").string());
  const auto pixels = volume_pixels(cool);
  ASSERT_GT(pixels.size(), size_t(cool.width * cool.height) / 20) << "the volume covers too little of the view";
  double difference = 0.0;
  for (size_t i : pixels)
    for (size_t k = 0; k < 3; ++k) difference += std::abs(int(cool.rgb[3 * i + k]) - int(black.rgb[3 * i + k]));
  EXPECT_GT(difference / double(pixels.size() * 3), 10.0) << "the transfer function did not change the image";

  // The panels are drawn: most pixels of the panel's column differ from the same frame without
  // them (the side panel is 45% of the width at this size, opaque enough to change every pixel
  // it covers; 30% leaves room for its transparent gaps).
  const Png ui = read_png((dir / "with-ui.png").string());
  size_t changed = 0, panel_pixels = 0;
  for (int y = 0; y < ui.height; ++y)
    for (int x = 0; x < ui.width * 2 / 5; ++x, ++panel_pixels)
      changed += std::memcmp(ui.at(x, y), black.at(x, y), 3) != 0;
  EXPECT_GT(changed, panel_pixels * 3 / 10);

  // "Render this view" gives the window's own picture: the same display image, encoded to
  // 8-bit sRGB once by the swapchain and once by the PNG writer (each rounds; 2 levels apart
  // at most).
  const Png render = read_png((dir / "render.png").string());
  ASSERT_EQ(render.width, black.width);
  int worst = 0;
  for (size_t i = 0; i < render.rgb.size(); ++i) worst = std::max(worst, std::abs(int(render.rgb[i]) - int(black.rgb[i])));
  EXPECT_LE(worst, 2);

  // The camera line re-creates the camera; the HUD's numbers describe the frame.
  ASSERT_EQ(report.camera_lines.size(), 1u);
  const Camera parsed = app::camera_from_line(report.camera_lines[0], bounds_of(mesh));
  EXPECT_NEAR(glm::distance(parsed.eye, report.camera.eye), 0.0, 1e-9);
  // The drags moved the camera: rotated (the eye off the +z axis), zoomed in (the fitted eye
  // is at its distance times 0.9 after one step of right drag), panned (target off the centre).
  const Camera fitted = fit_camera(bounds_of(mesh));
  EXPECT_GT(std::abs(report.camera.eye.x), 1e-3);
  EXPECT_NEAR(glm::distance(report.camera.eye, report.camera.target), 0.9 * glm::distance(fitted.eye, fitted.target), 1e-9);
  EXPECT_GT(glm::distance(report.camera.target, fitted.target), 1e-3);
  EXPECT_EQ(report.mode, "interval-sorted");
  EXPECT_EQ(report.quantity, volume::Quantity::Color);
  for (const char* pass : {"interval-shading (emission)", "resolve", "present-blit", "ui"}) EXPECT_TRUE(has_pass(report, pass)) << pass;
  // Sorted, or (a still camera at the end) drawn with the last sorted order.
  EXPECT_TRUE(has_pass(report, "sort") || report.last_frame.report().plan.reuses_order);
  EXPECT_EQ(report.last_frame.cells, mesh.tets.size());
  EXPECT_GT(report.last_frame.report().mesh_bytes, mesh.tets.size() * 16);
  if (report.last_frame.report().counted) {
    EXPECT_GT(report.last_frame.report().fragments, 0u);
  }
  // The panel's numbers are the typed stats `render` writes: the same writer reads them.
  const app::StatsJson js = app::frame_json(report.last_frame.frame, {});
  EXPECT_EQ(js["ordering"], report.last_frame.report().ordering);
  EXPECT_EQ(js["gpu_mesh_bytes"], report.last_frame.report().mesh_bytes);
  EXPECT_EQ(js["passes"].size(), report.last_frame.frame.passes.size());
  EXPECT_TRUE(fs::exists(dir / "tf.json"));
}

// Axis views look along their axis: +X shows the box's y-z face, +Z its x-y face. The
// silhouette is the near face's projection; its extent in pixels follows from the reported
// camera. Pixel centres decide coverage, so each edge is within one pixel: 2 in all.
TEST(Viewer, AxisViewsShowTheExpectedSilhouette) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("axis");
  const glm::dvec3 lo(-1.0, -0.3, -0.6), hi(1.0, 0.3, 0.6);
  // Dense enough that a ray through the box even 0.1 pixel inside an edge is visibly dark.
  const TetMesh box = make_box_mesh(lo, hi, 3, [](const glm::dvec3&) { return 60.0; });
  // +X through the panel's button command, +Z through its key (Z), which must do the same.
  struct Case { const char* view; const char* command; int horizontal_axis, vertical_axis, depth_axis; double near_face; };
  for (const Case& k : {Case{"+X", "view +X", 1, 2, 0, lo.x}, Case{"+Z", "key Z", 0, 1, 2, lo.z}}) {
    const std::string shot = (dir / (std::string(k.view) + ".png")).string();
    app::ViewerOptions options =
        window_options(320, 240, std::string("frame 1\nui off\nrotate 40 30\n") + k.command + "\nframe 3\nscreenshot " + shot + "\nframe 4\nclose\n");
    const app::ViewerReport report = app::run_viewer(box, options);
    EXPECT_EQ(report.validation_messages, 0u);
    const Png png = read_png(shot);
    int min_x = png.width, max_x = -1, min_y = png.height, max_y = -1;
    for (int y = 0; y < png.height; ++y)
      for (int x = 0; x < png.width; ++x)
        if (png.at(x, y)[0] < 200) {
          min_x = std::min(min_x, x), max_x = std::max(max_x, x);
          min_y = std::min(min_y, y), max_y = std::max(max_y, y);
        }
    const Camera& c = report.camera;
    const double depth = std::abs(c.eye[k.depth_axis] - k.near_face);
    const double pixels_per_unit = png.height / 2.0 / (depth * std::tan(glm::radians(c.fovy_degrees) / 2.0));
    const double width = (hi[k.horizontal_axis] - lo[k.horizontal_axis]) * pixels_per_unit;
    const double height = (hi[k.vertical_axis] - lo[k.vertical_axis]) * pixels_per_unit;
    EXPECT_NEAR(max_x - min_x + 1, width, 2.0) << k.view;
    EXPECT_NEAR(max_y - min_y + 1, height, 2.0) << k.view;
    EXPECT_NEAR((min_x + max_x + 1) / 2.0, png.width / 2.0, 1.0) << k.view << ": not centred";
  }
}

// Fly mode moves the eye into the volume: from the centre of a dense box every pixel's ray
// crosses at least 0.3 units of medium (the nearest face), an optical depth of 18 at sigma 60,
// so the whole image is the medium's colour; a near plane that cut the cells around the eye
// would leave background showing. Transmittance uses the clipping of cells at the near plane.
TEST(Viewer, FlyingIntoTheVolumeSeesMediumInEveryDirection) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("fly");
  const glm::dvec3 lo(-1.0, -0.3, -0.6), hi(1.0, 0.3, 0.6);
  const TetMesh box = make_box_mesh(lo, hi, 3, [](const glm::dvec3&) { return 60.0; });
  // The fitted eye looks at the centre from +z; fly forward by that distance (speed: a fifth of
  // the diagonal per second), then look sideways.
  const Camera start = fit_camera(bounds_of(box));
  const double speed = glm::length(hi - lo) / 5.0;
  std::ostringstream script;
  script.precision(17);
  script << "frame 1\nui off\nfly on\nfly-move 0 0 1 " << glm::distance(start.eye, start.target) / speed << "\n"
         << "frame 3\nscreenshot " << (dir / "ahead.png").string() << "\n"
         << "frame 4\nfly-look 120 0\nframe 6\nscreenshot " << (dir / "side.png").string() << "\nframe 7\nclose\n";
  app::ViewerOptions options = window_options(200, 150, script.str());
  const app::ViewerReport report = app::run_viewer(box, options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_NEAR(glm::distance(report.camera.eye, glm::dvec3(0.0)), 0.0, 1e-9);
  for (const char* name : {"ahead.png", "side.png"}) {
    const Png png = read_png((dir / name).string());
    size_t background = 0;
    for (int y = 0; y < png.height; ++y)
      for (int x = 0; x < png.width; ++x) background += png.at(x, y)[0] > 200;
    EXPECT_EQ(background, 0u) << name << ": background shows from inside the volume";
  }
}

// Rapid mode, quantity and transfer-function switching for 1000 frames, panels on: no crash,
// no validation message, and no steady memory growth. Resident memory is sampled after frame
// 200 (caches, pipelines and tables of every mode already made) and after frame 1000; the bound
// (4 MiB over 800 frames, 5 KiB a frame; about 0.1 MiB measured on lavapipe) is far below what leaking one frame's targets or
// per-frame command state would cost (the targets alone are 160x120x(16+16+4) bytes, 0.7 MB).
TEST(Viewer, ThousandFramesOfModeSwitchingNeitherCrashNorGrow) {
  REQUIRE_DISPLAY();
  std::ostringstream script;
  const char* modes[] = {"interval", "interval-sorted", "interval-exact-order"};
  const char* quantities[] = {"optical-depth", "color", "transmittance", "color"};
  const char* presets[] = {"viridis", "grayscale", "black-body", "cool-to-warm"};
  for (int f = 1; f < 1000; f += 3) {
    const int i = f / 3;
    script << "frame " << f << "\nmode " << modes[i % 3] << "\nquantity " << quantities[(i / 3) % 4] << "\ntf " << presets[(i / 2) % 4]
           << "\n";
    if (i % 7 == 0) script << "tetlet-size " << (i % 2 ? 4 : 16) << "\n";
    if (i % 11 == 0) script << "rotate 13 7\n";
    if (f == 199) script << "frame 200\nrss\n";
  }
  script << "frame 1000\nrss\nclose\n";
  app::ViewerOptions options = window_options(160, 120, script.str());
  const app::ViewerReport report = app::run_viewer(make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 3,
                                                                 [](const glm::dvec3& p) { return 1.0 + p.x; }),
                                                   options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_TRUE(report.messages.empty()) << report.messages.front();
  // Frames 0..1000: the close request of frame 1000 is seen at the top of frame 1001.
  EXPECT_EQ(report.frames_presented + report.frames_skipped_minimized, 1001u);
  ASSERT_EQ(report.resident_kib.size(), 2u);
  const int64_t growth = int64_t(report.resident_kib[1].second) - int64_t(report.resident_kib[0].second);
  std::cout << "resident memory: " << report.resident_kib[0].second << " KiB after frame 200, " << report.resident_kib[1].second
            << " KiB after frame 1000\n";
  EXPECT_LT(growth, 4 * 1024);
}

// The command line's view verb with a script: exit status 0 and the script's screenshot.
TEST(Viewer, ViewVerbRunsAScriptAndExitsCleanly) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("verb");
  std::ofstream(dir / "s.txt") << "frame 2\nscreenshot " << (dir / "shot.png").string() << "\nframe 3\nclose\n";
  const int status = app::run_cli({"view", "ball:1", "--size", "160x120", "--validate", "--script", (dir / "s.txt").string()});
  EXPECT_EQ(status, 0);
  EXPECT_TRUE(fs::exists(dir / "shot.png"));
}

// The cube (tests/support/cube_surface.hpp) in `dir`, with a fresh TetGen cache there so the
// fill really runs.
fs::path write_cube_off(const fs::path& dir) {
  const fs::path path = dir / "cube.off";
  test::write_cube_off(path);
  setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);
  return path;
}

// A surface filled by TetGen in the background: frames keep being presented while it loads,
// and then both datasets are drawn (the cells drawn are the sum of theirs).
TEST(ViewerLoading, OpensASecondDatasetWhileTheWindowKeepsDrawing) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("open");
  const fs::path cube = write_cube_off(dir);
  app::ViewerOptions options = window_options(200, 150, "frame 1\nopen " + cube.string() + "\nwait-load\nframe 3\nclose\n");
  options.open_defaults.tetgen.max_volume = 2e-5;  // tens of thousands of cells: a load of many frames
  const TetMesh first = make_default_volume();
  const app::ViewerReport report = app::run_viewer(first, options);
  EXPECT_EQ(report.validation_messages, 0u);
  ASSERT_EQ(report.loads.size(), 1u);
  const app::LoadRecord& load = report.loads[0];
  ASSERT_TRUE(load.loaded) << load.error;
  EXPECT_GT(load.frames_presented, 0u) << "the window froze during the load (" << load.seconds << " s)";
  EXPECT_GE(load.cells, size_t(1.0 / 2e-5));  // the bound caps each cell's volume
  EXPECT_EQ(report.datasets, 2u);
  EXPECT_EQ(report.datasets_visible, 2u);
  EXPECT_EQ(report.last_frame.cells, first.tets.size() + load.cells);
  std::cout << "TetGen load: " << load.cells << " cells in " << load.seconds << " s, " << load.frames_presented
            << " frames presented meanwhile\n";
}

// A time series in the window (issue "Simulations as they come"): three steps of the box [-1,1]^3,
// each of one extinction. Stepping shows each step (its optical depth along the axis is 2 sigma
// of that step), playing walks the steps and wraps around, the steps load beside the frames,
// and the mesh is uploaded once: every later step sends its fields alone. Validation stays silent.
const std::vector<double> kStepSigma = {0.5, 1.0, 2.0};

// The window's state for a .pvd of three steps of the box, written in `dir`, opened at step 0.
app::ViewState box_series_state(const fs::path& dir) {
  const std::vector<double>& sigma = kStepSigma;
  std::ofstream pvd(dir / "series.pvd");
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n";
  for (size_t i = 0; i < sigma.size(); ++i) {
    const double s = sigma[i];
    io::write_tet_mesh_vtu((dir / ("box_" + std::to_string(i) + ".vtu")).string(),
                           make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 2, [s](const glm::dvec3&) { return s; }));
    pvd << "    <DataSet timestep=\"" << i << "\" part=\"0\" file=\"box_" << i << ".vtu\"/>\n";
  }
  pvd << "  </Collection>\n</VTKFile>\n";
  pvd.close();
  app::LoadRequest request;
  request.path = (dir / "series.pvd").string();
  request.array = "extinction";
  app::ViewState state;
  state.datasets.push_back(app::make_dataset(app::load_dataset(request)));
  app::attach_time(state.datasets.back(), request);
  return state;
}

using test::box_view;

TEST(ViewerLoading, StepsAndPlaysATimeSeriesUploadingItsMeshOnce) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("time");
  const std::vector<double>& sigma = kStepSigma;
  app::ViewState state = box_series_state(dir);
  ASSERT_EQ(state.datasets.back().times.size(), 3u);

  std::ostringstream script;
  const auto render = [&](const std::string& name) { script << "wait 2\nrender 9 9 " << (dir / name).string() << "\n"; };
  script << "wait 2\ntime-step 1\nwait-load\n";
  render("s1.pfm");
  script << "time-step 2\nwait-load\n";
  render("s2.pfm");
  script << "play on\nwait-step 0 60\nwait-step 1 60\nplay off\nwait-load\n";
  render("played.pfm");
  script << "time-step 7\nclose\n";
  app::ViewerOptions options = window_options(160, 120, script.str());
  options.settings.resolve.quantity = volume::Quantity::OpticalDepth;
  options.camera = box_view();
  const app::ViewerReport report = app::run_viewer(std::move(state), options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_EQ(report.steps_shown, (std::vector<uint32_t>{1, 2, 0, 1}));
  EXPECT_EQ(report.mesh_uploads, 1u);
  EXPECT_EQ(report.field_uploads, report.steps_shown.size());
  // The centre pixel's ray is the axis: 2 sigma of the step shown (float32: 1e-5 relative).
  const auto centre = [&](const std::string& name) { return test::box_view_centre(io::read_pfm((dir / name).string()).pixels); };
  EXPECT_NEAR(centre("s1.pfm"), 2.0 * sigma[1], 2e-5 * sigma[1]);
  EXPECT_NEAR(centre("s2.pfm"), 2.0 * sigma[2], 2e-5 * sigma[2]);
  EXPECT_NEAR(centre("played.pfm"), 2.0 * sigma[1], 2e-5 * sigma[1]);
  // A step that does not exist is refused by name; the window goes on to close.
  ASSERT_FALSE(report.messages.empty());
  EXPECT_NE(report.messages.back().find("has 3 steps (0 to 2), not 7"), std::string::npos) << report.messages.back();
}

// The split view compares two steps: B at another step of the series. The view is symmetric
// about its vertical axis, so with B at A's own step the two halves' mirrored pixels agree, and
// with B at another step (another extinction) they differ.
TEST(ViewerLoading, SplitViewComparesTwoSteps) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("compare-steps");
  std::ostringstream script;
  script << "ui off\nwait 2\ntime-step 2\nwait-load\ncompare-step 2\nwait-load\nwait 3\nscreenshot " << (dir / "same.png").string()
         << "\ncompare-step 0\nwait-load\nwait 3\nscreenshot " << (dir / "two.png").string() << "\ncompare-step 9\nclose\n";
  app::ViewerOptions options = window_options(160, 120, script.str());
  options.settings.resolve.quantity = volume::Quantity::OpticalDepth;
  options.camera = box_view();
  const app::ViewerReport report = app::run_viewer(box_series_state(dir), options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_EQ(report.steps_shown, std::vector<uint32_t>{2});
  // Pixels at 3/8 and 5/8 of the width on the middle row: A's half and B's, mirror images.
  const auto halves = [&](const std::string& name) {
    const Png png = read_png((dir / name).string());
    const int y = png.height / 2, left = png.width * 3 / 8, right = png.width - 1 - left;
    int largest = 0;
    for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(int(png.at(left, y)[c]) - int(png.at(right, y)[c])));
    return largest;
  };
  EXPECT_LE(halves("same.png"), 2) << "B at A's step should mirror A";
  EXPECT_GE(halves("two.png"), 20) << "B at step 0 (extinction 0.5) should differ from A at step 2 (2.0)";
  ASSERT_FALSE(report.messages.empty());
  EXPECT_NE(report.messages.back().find("compare-step:"), std::string::npos) << report.messages.back();
  EXPECT_NE(report.messages.back().find("not 9"), std::string::npos) << report.messages.back();
}

// Bad files (missing, truncated) give the data layer's message naming the file; the window
// keeps running and opens the next file (dropped), and hiding a dataset changes what is drawn.
TEST(ViewerLoading, BadFilesReportTheirErrorAndTheWindowStaysUsable) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("bad");
  const fs::path missing = dir / "missing.vtu", truncated = dir / "truncated.vtu";
  std::ofstream(truncated) << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\">\n<UnstructuredGrid>\n<Piece";
  std::ostringstream script;
  script << "frame 1\nopen " << missing.string() << "\nwait-load\nopen " << truncated.string() << "\nwait-load\n"
         << "drop ball:1\nwait-load\nframe 3\nshow 0 off\nframe 5\nclose\n";
  const app::ViewerReport report = app::run_viewer(make_default_volume(), window_options(200, 150, script.str()));
  EXPECT_EQ(report.validation_messages, 0u);
  ASSERT_EQ(report.loads.size(), 3u);
  EXPECT_FALSE(report.loads[0].loaded);
  EXPECT_NE(report.loads[0].error.find(missing.string()), std::string::npos) << report.loads[0].error;
  EXPECT_FALSE(report.loads[1].loaded);
  EXPECT_NE(report.loads[1].error.find(truncated.string()), std::string::npos) << report.loads[1].error;
  EXPECT_EQ(report.last_load_error, report.loads[1].error);
  EXPECT_TRUE(report.loads[2].loaded) << report.loads[2].error;
  EXPECT_EQ(report.datasets, 2u);
  EXPECT_EQ(report.datasets_visible, 1u);
  EXPECT_EQ(report.last_frame.cells, 80u);  // the ball alone (20 cells, each split in 4)
  EXPECT_GE(report.frames_presented, 5u);
}

std::string file_bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Script commands on a bad file or size (a colour map that is a folder, an export to a folder,
// a render and a window size out of bounds, a screenshot or render over the dataset the window
// opened, a screenshot that is not a PNG) each open the error popup with their message; the window goes on, writes its next
// screenshot, leaves no temporary file, and the dataset keeps its bytes.
TEST(Viewer, BadFileAndSizeCommandsOpenTheErrorPopupAndTheWindowGoesOn) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("bad-commands");
  const std::string v = (dir / "v.vtu").string(), folder = (dir / "folder.json").string(), shot = (dir / "shot.png").string();
  io::write_tet_mesh_vtu(v, make_default_volume());
  const std::string before = file_bytes(v);
  fs::create_directory(folder);
  std::ostringstream script;
  script << "open " << v << "\nwait-load\ntf " << folder << "\ntf-export " << folder << "\nrender 100000 100000 " << (dir / "r.pfm").string()
         << "\nresize 0 0\nscreenshot " << v << "\nrender 16 16 " << v << "\nscreenshot " << (dir / "shot.jpg").string() << "\nwait 2\nscreenshot " << shot << "\nwait 4\nclose\n";
  app::ViewerOptions options = window_options(200, 150, script.str());
  options.settings.resolve.quantity = volume::Quantity::Color;
  const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
  EXPECT_EQ(report.validation_messages, 0u);
  const std::vector<std::string> expected = {
      "Could not open: test script:3: " + folder + ": is a folder, not a ParaView colour-map file",
      "Could not write: test script:4: " + folder + ": is a folder: tf-export needs a file name",
      "Could not write: test script:5: render: each side must be between 1 and 16384 pixels",
      "Refused: test script:6: resize: each side must be between 1 and 16384 pixels",
      "Could not write: test script:7: " + v + ": screenshot would write over a file this command reads: name another file",
      "Could not write: test script:8: " + v + ": render would write over a file this command reads: name another file",
      "Could not write: test script:9: " + (dir / "shot.jpg").string() + ": screenshot writes .png files, not .jpg"};
  EXPECT_EQ(report.error_popups, expected);
  EXPECT_EQ(report.files_written, std::vector<std::string>{shot});
  EXPECT_GE(report.frames_presented, 6u);
  EXPECT_EQ(file_bytes(v), before);
  for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename().string().find("partial"), std::string::npos) << e.path();
}

// Cancel on a slow load (over a million cells to fill): it stops, nothing is added, no crash.
// Closing the window mid-load cancels and waits for the load, and returns promptly.
TEST(ViewerLoading, CancelAndClosingMidLoadEndTheLoadCleanly) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("cancel");
  const fs::path cube = write_cube_off(dir);
  for (const char* ending : {"frame 4\ncancel-load\nwait-load 10\nframe 6\nclose\n", "frame 4\nclose\n"}) {
    // Cancelled by cancel-load, the load ends before the window closes; closed mid-load, the
    // window stops it.
    app::ViewerOptions options = window_options(160, 120, "frame 1\nopen " + cube.string() + "\n" + ending);
    options.open_defaults.tetgen.max_volume = 5e-7;
    const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
    EXPECT_EQ(report.validation_messages, 0u);
    EXPECT_EQ(report.loads_cancelled, 1u) << ending;
    EXPECT_EQ(report.datasets, 1u);
    // TetGen's runner checks for cancellation every 100 ms and kills its child; the fill alone
    // would take tens of seconds. 2 s leaves room for a loaded machine.
    EXPECT_LT(report.seconds_to_stop_load, 2.0) << ending;
  }
}

// `prismoid view a.vtu b.vtu`: both open in one scene, exit status 0, and both enter the
// recent-files list (the later first).
TEST(ViewerLoading, ViewVerbOpensSeveralFiles) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("several");
  io::write_tet_mesh_vtu((dir / "a.vtu").string(), make_default_volume());
  io::write_tet_mesh_vtu((dir / "b.vtu").string(), make_ball_mesh(glm::dvec3(3.0), 1.0, 2, 1.0));
  setenv("XDG_CONFIG_HOME", (dir / "config").c_str(), 1);
  const int status = app::run_cli({"view", (dir / "a.vtu").string(), (dir / "b.vtu").string(), "--size", "160x120", "--validate",
                                   "--frames", "5"});
  EXPECT_EQ(status, 0);
  std::ifstream recent(dir / "config" / "prismoid" / "recent.txt");
  std::string line1, line2;
  std::getline(recent, line1);
  std::getline(recent, line2);
  EXPECT_EQ(line1, (dir / "b.vtu").string());
  EXPECT_EQ(line2, (dir / "a.vtu").string());
}

// Split view: A's left half and B's right half on one camera, each exactly what that mode
// shows alone (the same display images, blitted 1:1, so equal up to nothing; 2 levels allow
// for a different rounding path), with the divider between them. A is colour in GPU-sorted
// order, B transmittance in exact order: they differ by far more than rounding.
TEST(Viewer, SplitViewShowsModeAOnTheLeftAndModeBOnTheRight) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("split");
  std::ostringstream script;
  script << "frame 1\nui off\nmode interval-sorted\nquantity color\ntf-range data\ndensity-scale 8\n"
         << "frame 3\nscreenshot " << (dir / "a.png").string() << "\n"
         << "frame 4\nmode interval-exact-order\nquantity transmittance\n"
         << "frame 6\nscreenshot " << (dir / "b.png").string() << "\n"
         << "frame 7\nmode interval-sorted\nquantity color\ncompare split\ncompare-mode interval-exact-order\n"
         << "compare-quantity transmittance\n"
         << "frame 10\nscreenshot " << (dir / "split.png").string() << "\nframe 11\nclose\n";
  app::ViewerOptions options = window_options(320, 240, script.str());
  const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_TRUE(report.messages.empty()) << report.messages.front();
  const Png a = read_png((dir / "a.png").string()), b = read_png((dir / "b.png").string());
  const Png split = read_png((dir / "split.png").string());
  ASSERT_EQ(split.width, 320);
  const int half = split.width / 2;  // the divider covers columns half - 1 and half
  int worst_a = 0, worst_b = 0;
  size_t a_unlike_b = 0;  // right-half pixels where A and B differ by more than 20 levels
  for (int y = 0; y < split.height; ++y)
    for (int x = 0; x < split.width; ++x) {
      int a_b = 0;
      for (int k = 0; k < 3; ++k) {
        if (x < half - 1) worst_a = std::max(worst_a, std::abs(int(split.at(x, y)[k]) - int(a.at(x, y)[k])));
        if (x > half) {
          worst_b = std::max(worst_b, std::abs(int(split.at(x, y)[k]) - int(b.at(x, y)[k])));
          a_b = std::max(a_b, std::abs(int(a.at(x, y)[k]) - int(b.at(x, y)[k])));
        }
      }
      a_unlike_b += a_b > 20;
    }
  EXPECT_LE(worst_a, 2) << "the left half is not mode A";
  EXPECT_LE(worst_b, 2) << "the right half is not mode B";
  // The volume covers about a sixth of the right half; most of it must tell A from B.
  EXPECT_GT(a_unlike_b, size_t(half * split.height) / 20) << "A and B look alike: the test proves nothing";
  // The divider: orange (linear 1, 0.45, 0; about 255, 180, 0 in sRGB) in every row.
  for (int y = 0; y < split.height; ++y)
    for (int x : {half - 1, half}) {
      const unsigned char* p = split.at(x, y);
      EXPECT_TRUE(p[0] > 240 && p[1] > 150 && p[1] < 210 && p[2] < 20) << "no divider at " << x << "," << y;
    }
  // Both modes' passes are timed: B's appear in the report beside A's.
  const auto& bp = report.compare_passes;
  EXPECT_TRUE(std::any_of(bp.begin(), bp.end(), [](const vk::PassTiming& t) { return t.name == "interval-shading"; }));
  // A (sorted colour) sorts, unless its camera was still and the planner reused the order.
  EXPECT_TRUE(has_pass(report, "sort") || report.last_frame.report().plan.reuses_order);
}

// The camera as `render` options, split into words for run_cli.
std::vector<std::string> camera_args(const std::string& line) {
  std::istringstream words(line);
  std::vector<std::string> args;
  for (std::string w; words >> w;) args.push_back(w);
  return args;
}

io::FloatImage render_with_cli(const std::vector<std::string>& camera, const std::string& mode, const std::string& quantity,
                               const fs::path& out) {
  std::vector<std::string> args = {"render", "--mode", mode, "--quantity", quantity, "--size", "200x150", "--output", out.string()};
  args.insert(args.end(), camera.begin(), camera.end());
  EXPECT_EQ(app::run_cli(args), 0);
  return io::read_pfm(out.string());
}

// Difference view: the statistics it prints are image_error of the GPU frame against the CPU
// reference, the same numbers a user gets from two `prismoid render`s of this camera and size;
// colour in mesh order (no visibility order at all) is further from the reference than in exact
// order; the heat map replaces the view (black where nothing differs, white at the largest
// error).
TEST(Viewer, DifferenceViewReportsTheErrorOfTheModeAgainstTheReference) {
  REQUIRE_DISPLAY();
  const fs::path dir = out_dir("difference");
  std::ostringstream script;
  script << "frame 1\nui off\nmode interval\nquantity optical-depth\ncompare difference\nwait-reference 120\n"
         << "wait 2\nscreenshot " << (dir / "heat.png").string() << "\nprint-camera\n"
         << "wait 1\nquantity color\ntf-range data\ndensity-scale 8\nwait-reference 120\n"
         << "wait 1\nmode interval-exact-order\nwait-reference 120\nwait 1\nclose\n";
  app::ViewerOptions options = window_options(200, 150, script.str());
  options.max_frames = 1000000;  // the references take seconds; wait-reference's timeout is the limit
  const auto start = std::chrono::steady_clock::now();
  const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
  std::cout << "difference session: " << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_TRUE(report.messages.empty()) << report.messages.front();
  ASSERT_EQ(report.comparisons.size(), 3u);
  ASSERT_EQ(report.camera_lines.size(), 1u);

  const app::FrameComparison& depth = report.comparisons[0];
  EXPECT_EQ(depth.channels, "optical depth");
  ASSERT_EQ(depth.width, 200u);
  ASSERT_EQ(depth.height, 150u);
  const auto camera = camera_args(report.camera_lines[0]);
  const io::FloatImage ref = render_with_cli(camera, "reference", "optical-depth", dir / "ref.pfm");
  const io::FloatImage gpu = render_with_cli(camera, "interval", "optical-depth", dir / "gpu.pfm");
  const double peak = *std::max_element(ref.pixels.begin(), ref.pixels.end());
  const reference::ImageError expected = reference::image_error(gpu.pixels, ref.pixels, peak);
  // Same code, same inputs: equal up to float rounding of the images (one ulp of the peak).
  EXPECT_NEAR(depth.error.rmse, expected.rmse, 1e-6 * peak);
  EXPECT_NEAR(depth.error.max_abs, expected.max_abs, 1e-6 * peak);
  EXPECT_NEAR(depth.peak, peak, 1e-6 * peak);
  EXPECT_EQ(depth.error.non_finite, 0u);
  EXPECT_GT(peak, 0.5);
  EXPECT_LT(depth.error.rmse, 1e-3 * peak);  // the CLI tests' bound (tests/app/test_cli.cpp)
  EXPECT_GT(depth.error.rmse, 0.0) << "a float renderer equal to a double reference everywhere: suspicious";

  const app::FrameComparison& unordered = report.comparisons[1];
  const app::FrameComparison& exact = report.comparisons[2];
  EXPECT_EQ(exact.channels, "display RGB");
  EXPECT_EQ(unordered.error.non_finite, 0u);
  EXPECT_EQ(exact.error.non_finite, 0u);
  EXPECT_TRUE(std::isfinite(exact.error.rmse) && std::isfinite(unordered.error.rmse));
  EXPECT_GT(unordered.error.rmse, 3.0 * exact.error.rmse) << "mesh order should be visibly wrong for colour";
  EXPECT_LT(exact.error.rmse, 2e-3);  // the CLI's 1e-3 for colour, and as much again for the background seen through it

  // The heat map: zero error outside the volume is black; the worst pixel is white.
  const Png heat = read_png((dir / "heat.png").string());
  EXPECT_LE(int(heat.at(0, 0)[0]) + heat.at(0, 0)[1] + heat.at(0, 0)[2], 3);
  bool white = false;
  for (int y = 0; y < heat.height; ++y)
    for (int x = 0; x < heat.width; ++x) white = white || (heat.at(x, y)[0] > 250 && heat.at(x, y)[1] > 250 && heat.at(x, y)[2] > 250);
  EXPECT_TRUE(white) << "no pixel at the heat map's maximum";
}

// Closing the window while the reference is still being computed returns promptly and cleanly:
// the worker is waited for (references cannot be interrupted), so at most one reference's time.
TEST(Viewer, ClosingWhileTheReferenceComputesExitsCleanly) {
  REQUIRE_DISPLAY();
  app::ViewerOptions options =
      window_options(320, 240, "frame 1\nquantity color\ntf-range data\ncompare difference\nwait-reference 0.5\nclose\n");
  options.max_frames = 1000000;
  const auto start = std::chrono::steady_clock::now();
  const app::ViewerReport report = app::run_viewer(make_default_volume(), options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "closed after " << seconds << " s\n";
  EXPECT_EQ(report.validation_messages, 0u);
  ASSERT_EQ(report.messages.size(), 1u);
  EXPECT_EQ(report.messages[0], "wait-reference: timed out");  // the reference was still running at close
  EXPECT_TRUE(report.comparisons.empty());
  EXPECT_LT(seconds, 20.0);
}

}  // namespace
}  // namespace prismoid
