// The surface window under Xvfb, driven by a script: it draws the forward backend's image (the
// one tests/surface holds to the CPU direct-light reference), its `render` verb writes that
// image, the screenshot shows it as the swapchain encodes it, modes it cannot draw are
// refused with a message, the camera verbs move the camera, and the validation layer stays
// silent.
#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <glm/geometric.hpp>

#include "app/viewer/camera_line.hpp"
#include "app/viewer/surface_viewer.hpp"
#include "io/image_io.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "renderer/surface/htex/htex_pass.hpp"
#include "renderer/surface/htex/htex_backend.hpp"
#include "renderer/surface/msa/msa_pass.hpp"
#include "renderer/surface/texel/texel_pass.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "scene/surface_generators.hpp"
#include "surface/forward_comparison.hpp"

namespace prismoid {
namespace {

namespace fs = std::filesystem;

std::vector<unsigned char> read_rgb(const fs::path& path, int& width, int& height) {
  int channels = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &width, &height, &channels, 3);
  if (!data) throw std::runtime_error("cannot read " + path.string());
  std::vector<unsigned char> rgb(data, data + size_t(width) * size_t(height) * 3);
  stbi_image_free(data);
  return rgb;
}

TEST(SurfaceViewer, DrawsTheForwardImageSwitchesModesAndMovesTheCamera) {
  ASSERT_TRUE(app::display_available()) << "this test needs a display: run it through scripts/test.sh, which starts Xvfb";
  const fs::path dir = fs::temp_directory_path() / "prismoid-surface-viewer";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const SurfaceScene scene = with_default_lighting(make_cornell_box(), make_cornell_box().camera);
  app::ViewerOptions options;
  options.width = 160;
  options.height = 120;
  options.validation = true;
  options.print_timings = false;
  options.max_frames = 500;
  options.script = app::parse_script("frame 2\nui off\nshadows off\nframe 3\nscreenshot " + (dir / "plain.png").string() + "\nrender 160 120 " +
                                         (dir / "render.pfm").string() + "\nrender 160 120 " + (dir / "render.png").string() +
                                         "\nframe 4\nshadows on\nrender 160 120 " + (dir / "shadowed.pfm").string() +
                                         "\nmode htex\nrender 160 120 " + (dir / "htex.pfm").string() + "\nmode texel\nrender 160 120 " +
                                         (dir / "texel.pfm").string() + "\nmode msa\nrender 160 120 " + (dir / "msa.pfm").string() + "\nkey T\nkey T\nkey K\nframe 2\nrender 160 120 " +
                                         (dir / "msa_conformal.pfm").string() + "\nmode forward" +
                                         "\nmode no-such-mode\nkey M\nframe 5\nui on\nscreenshot " + (dir / "ui.png").string() +
                                         "\nframe 6\nmode htex-gi\nrotate 40 0\nzoom 1\nprint-camera\ntetlet-size 4\nframe 8\nclose\n",
                                     "test script");
  const app::ViewerReport report = app::run_surface_viewer(scene, options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_EQ(report.mode, "htex-gi");  // M cycled from forward to htex; the script then chose GI
  EXPECT_EQ(report.msa_amortization, 8u);  // T twice: every 4th, then every 8th frame
  EXPECT_EQ(report.msa_charts, "conformal");  // K
  ASSERT_EQ(report.files_written.size(), 9u);

  // Refused: an unknown mode, and a volume verb; each named in a message.
  ASSERT_EQ(report.messages.size(), 2u);
  EXPECT_NE(report.messages[0].find("unknown surface mode no-such-mode"), std::string::npos) << report.messages[0];
  EXPECT_NE(report.messages[1].find("not available in the surface window"), std::string::npos) << report.messages[1];

  // The window's render is the forward image, which holds to the CPU reference.
  vk::Instance instance(vk::InstanceOptions{.validation = true});
  const auto devices = vk::query_devices(instance.get());
  vk::Device device(instance, vk::select_device(devices, std::nullopt), {});
  surface::ForwardPass pass(device);
  const test::ForwardComparison cmp = test::compare_forward(device, pass, scene, scene.camera, 160, 120);
  EXPECT_EQ(cmp.failures, 0u) << cmp.first_failure;
  EXPECT_GT(cmp.compared, 160u * 120u / 2);
  const io::FloatImage render = io::read_pfm((dir / "render.pfm").string());
  ASSERT_EQ(render.width, 160u);
  ASSERT_EQ(render.channels, 3u);
  double worst = 0.0;
  for (size_t p = 0; p < size_t(160) * 120; ++p)
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(double(render.pixels[3 * p + c]) - double(cmp.gpu.rgba[4 * p + c])));
  EXPECT_LE(worst, 1e-6);  // the same device and code: the same floats up to rasterization order

  // With shadows on (the window's default where the device traces rays and the scene has
  // lights), the window's render is the shadowed pass's image, which holds to the CPU twin.
  surface::ShadowedForwardPass shadowed_pass(device);
  const test::ForwardComparison shadowed = test::compare_forward_shadowed(device, shadowed_pass, scene, scene.camera, 160, 120);
  EXPECT_EQ(shadowed.failures, 0u) << shadowed.first_failure;
  const io::FloatImage shadowed_render = io::read_pfm((dir / "shadowed.pfm").string());
  double shadowed_worst = 0.0;
  size_t darker = 0;
  for (size_t p = 0; p < size_t(160) * 120; ++p)
    for (int c = 0; c < 3; ++c) {
      shadowed_worst = std::max(shadowed_worst, std::abs(double(shadowed_render.pixels[3 * p + c]) - double(shadowed.gpu.rgba[4 * p + c])));
      darker += shadowed_render.pixels[3 * p + c] < render.pixels[3 * p + c] - 1e-3f;
    }
  EXPECT_LE(shadowed_worst, 1e-6);
  EXPECT_GT(darker, 100u);  // the blocks' shadows on the floor

  // In htex mode the window's render is the Htex backend's image of that camera (which
  // tests/surface holds to the CPU Htex lookup of CPU-shaded texels).
  {
    const SurfaceScene& lit = scene;
    const surface::GpuSurfaceScene gpu = surface::upload(device, lit);
    const rt::SceneAccel accel(device, lit);
    const surface::HtexGeometry geometry(lit, htex::LayoutOptions{.texels_per_unit = surface::htex_texels_per_unit(lit)});
    surface::HtexPass htex_pass(device, geometry, {});
    const surface::HtexImage htex = surface::render_htex(device, htex_pass, gpu, accel.tlas(), scene.camera, {160, 120});
    const io::FloatImage htex_render = io::read_pfm((dir / "htex.pfm").string());
    double htex_worst = 0.0, against_forward = 0.0;
    for (size_t p = 0; p < size_t(160) * 120; ++p)
      for (int c = 0; c < 3; ++c) {
        htex_worst = std::max(htex_worst, std::abs(double(htex_render.pixels[3 * p + c]) - double(htex.rgba[4 * p + c])));
        against_forward += std::abs(double(htex_render.pixels[3 * p + c]) - double(shadowed_render.pixels[3 * p + c]));
      }
    EXPECT_LE(htex_worst, 1e-6);
    EXPECT_GT(against_forward, 0.0);  // a different backend: not the forward image again
    EXPECT_EQ(htex.counters.hole_pixels, 0u);
    // texel and msa likewise: the window's renders are their backends' images (tests/surface
    // holds those to the CPU lookups of CPU-shaded texels).
    const texel::TexelAtlas atlas = surface::build_texel_atlas_for(device, lit);
    surface::TexelPass texel_pass(device, atlas, {});
    const surface::TexelImage texel = surface::render_texel(device, texel_pass, gpu, accel.tlas(), scene.camera, {160, 120});
    const msa::MeshletSet meshlets = msa::build_meshlets(lit);
    surface::MsaPass msa_pass(device, meshlets, {});
    const surface::MsaImage msa = surface::render_msa(device, msa_pass, gpu, accel.tlas(), scene.camera, {160, 120});
    const io::FloatImage texel_render = io::read_pfm((dir / "texel.pfm").string()), msa_render = io::read_pfm((dir / "msa.pfm").string());
    double texel_worst = 0.0, msa_worst = 0.0;
    for (size_t p = 0; p < size_t(160) * 120; ++p)
      for (int c = 0; c < 3; ++c) {
        texel_worst = std::max(texel_worst, std::abs(double(texel_render.pixels[3 * p + c]) - double(texel.rgba[4 * p + c])));
        msa_worst = std::max(msa_worst, std::abs(double(msa_render.pixels[3 * p + c]) - double(msa.rgba[4 * p + c])));
      }
    EXPECT_LE(texel_worst, 1e-6);
    EXPECT_LE(msa_worst, 1e-6);
    EXPECT_EQ(texel.counters.hole_pixels, 0u);
    EXPECT_EQ(msa.counters.hole_pixels, 0u);
    // After K the window's msa render is the conformal charts' image.
    const msa::MeshletSet conformal = msa::build_meshlets(lit, {.parametrization = msa::Parametrization::Conformal});
    surface::MsaPass conformal_pass(device, conformal, {});
    const surface::MsaImage conformal_image = surface::render_msa(device, conformal_pass, gpu, accel.tlas(), scene.camera, {160, 120});
    const io::FloatImage conformal_render = io::read_pfm((dir / "msa_conformal.pfm").string());
    double conformal_worst = 0.0;
    for (size_t p = 0; p < size_t(160) * 120; ++p)
      for (int c = 0; c < 3; ++c)
        conformal_worst = std::max(conformal_worst, std::abs(double(conformal_render.pixels[3 * p + c]) - double(conformal_image.rgba[4 * p + c])));
    EXPECT_LE(conformal_worst, 1e-6);
  }
  // The panel's count of what the last frame shaded.
  EXPECT_TRUE(report.last_frame.report().counted);
  EXPECT_GT(report.last_frame.report().fragments, 0u);

  // The screenshot is that image encoded to 8-bit sRGB by the swapchain's blit, the PNG by the
  // writer: each rounds once, so they are at most 2 levels apart.
  int w = 0, h = 0, w2 = 0, h2 = 0;
  const auto plain = read_rgb(dir / "plain.png", w, h);
  const auto rendered = read_rgb(dir / "render.png", w2, h2);
  ASSERT_EQ(w, w2);
  ASSERT_EQ(h, h2);
  int levels = 0;
  for (size_t i = 0; i < plain.size(); ++i) levels = std::max(levels, std::abs(int(plain[i]) - int(rendered[i])));
  EXPECT_LE(levels, 2);
  // With the panel on, its corner of the window changes.
  const auto with_ui = read_rgb(dir / "ui.png", w, h);
  size_t changed = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 60; ++x) changed += std::memcmp(&with_ui[(size_t(y) * w + x) * 3], &plain[(size_t(y) * w + x) * 3], 3) != 0;
  EXPECT_GT(changed, 40u * 60u / 2);

  // The camera verbs moved the camera: rotated about the target, one zoom step in.
  const Camera& start = scene.camera;
  EXPECT_GT(glm::distance(report.camera.eye, start.eye), 1e-3);
  EXPECT_NEAR(glm::distance(report.camera.target, start.target), 0.0, 1e-9);
  EXPECT_LT(glm::distance(report.camera.eye, report.camera.target), glm::distance(start.eye, start.target));
  ASSERT_EQ(report.camera_lines.size(), 1u);
  const Camera parsed = app::camera_from_line(report.camera_lines[0], bounds_of(scene));
  EXPECT_NEAR(glm::distance(parsed.eye, report.camera.eye), 0.0, 1e-9);
  // Every pass the last (Htex + ReSTIR GI) frame ran has a time.
  std::vector<std::string> names;
  for (const auto& p : report.last_frame.frame.passes) names.push_back(p.name);
  for (const char* pass_name : {"pre-z + marking", "allocation", "shading", "gi initial+temporal", "gi spatial", "gather", "present-blit", "ui"})
    EXPECT_NE(std::find(names.begin(), names.end(), pass_name), names.end()) << pass_name;
}

// A size out of bounds for `render` or `resize`, and a screenshot or render over the scene's
// file, are refused with a message and the window goes on; the file keeps its bytes.
TEST(SurfaceViewer, BadSizesAndOutputsOverTheSceneAreRefusedAndTheWindowGoesOn) {
  ASSERT_TRUE(app::display_available()) << "this test needs a display: run it through scripts/test.sh, which starts Xvfb";
  const fs::path dir = fs::temp_directory_path() / "prismoid-surface-viewer-refusals";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string scene_file = (dir / "scene.png").string();  // an input that looks like an image
  std::ofstream(scene_file) << "the scene's own bytes";
  app::ViewerOptions options;
  options.width = 120;
  options.height = 90;
  options.validation = true;
  options.print_timings = false;
  options.max_frames = 200;
  options.inputs = {scene_file};
  options.script = app::parse_script("frame 2\nrender 100000 100000 " + (dir / "r.pfm").string() + "\nresize 0 0\nscreenshot " + scene_file +
                                         "\nrender 8 8 " + scene_file + "\nframe 3\nrender 8 8 " + (dir / "ok.pfm").string() + "\nframe 5\nclose\n",
                                     "test script");
  const SurfaceScene scene = with_default_lighting(make_cornell_box(), make_cornell_box().camera);
  const app::ViewerReport report = app::run_surface_viewer(scene, options);
  EXPECT_EQ(report.validation_messages, 0u);
  ASSERT_EQ(report.messages.size(), 4u);
  EXPECT_NE(report.messages[0].find("test script:2: render: each side must be between 1 and 16384 pixels"), std::string::npos) << report.messages[0];
  EXPECT_NE(report.messages[1].find("test script:3: resize: each side must be between 1 and 16384 pixels"), std::string::npos) << report.messages[1];
  EXPECT_NE(report.messages[2].find(scene_file + ": screenshot would write over a file this command reads"), std::string::npos) << report.messages[2];
  EXPECT_NE(report.messages[3].find(scene_file + ": render would write over a file this command reads"), std::string::npos) << report.messages[3];
  EXPECT_EQ(report.files_written, std::vector<std::string>{(dir / "ok.pfm").string()});
  std::ifstream in(scene_file);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "the scene's own bytes");
}

// The split view: the left half is the left mode's image as it shows alone, the right half the
// right mode's (htex-gi: its indirect light in place of the sky's ambient term changes most
// pixels, so a right half from the left mode, or a swap, would fail), and both modes' passes
// are reported.
TEST(SurfaceViewer, SplitViewShowsTwoModesSideBySide) {
  ASSERT_TRUE(app::display_available()) << "this test needs a display: run it through scripts/test.sh, which starts Xvfb";
  const fs::path dir = fs::temp_directory_path() / "prismoid-surface-split";
  fs::remove_all(dir);
  fs::create_directories(dir);
  app::ViewerOptions options;
  options.width = 160;
  options.height = 120;
  options.validation = true;
  options.print_timings = false;
  options.max_frames = 200;
  options.script = app::parse_script("frame 2\nui off\nshadows off\nmode forward\nframe 3\nscreenshot " + (dir / "forward.png").string() +
                                         "\ncompare-mode htex-gi\ncompare split\nframe 12\nscreenshot " + (dir / "split.png").string() +
                                         "\nframe 13\ncompare bogus\nframe 14\nclose\n",
                                     "test script");
  const SurfaceScene scene = with_default_lighting(make_cornell_box(), make_cornell_box().camera);
  const app::ViewerReport report = app::run_surface_viewer(scene, options);
  EXPECT_EQ(report.validation_messages, 0u);
  EXPECT_EQ(report.mode, "forward");
  EXPECT_EQ(report.compare_mode, "htex-gi");
  std::vector<std::string> right;
  for (const auto& p : report.compare_passes) right.push_back(p.name);
  EXPECT_NE(std::find(right.begin(), right.end(), "present-blit"), right.end());
  EXPECT_NE(std::find(right.begin(), right.end(), "gather"), right.end()) << "htex-gi's passes";
  ASSERT_EQ(report.messages.size(), 1u);  // compare bogus
  EXPECT_NE(report.messages[0].find("compare takes split or off"), std::string::npos) << report.messages[0];
  int w = 0, h = 0, w2 = 0, h2 = 0;
  const std::vector<unsigned char> alone = read_rgb(dir / "forward.png", w, h);
  const std::vector<unsigned char> split = read_rgb(dir / "split.png", w2, h2);
  ASSERT_EQ(w, w2);
  ASSERT_EQ(h, h2);
  size_t left_differs = 0, right_differs = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool differs = false;
      for (int c = 0; c < 3; ++c) {
        const size_t i = (size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(c);
        differs = differs || std::abs(int(alone[i]) - int(split[i])) > 2;
      }
      (x < w / 2 ? left_differs : right_differs) += differs;
    }
  EXPECT_EQ(left_differs, 0u);
  EXPECT_GT(right_differs, size_t(w * h) / 4) << "the right half shows the forward image, not htex-gi's";
}

}  // namespace
}  // namespace prismoid
