// VTK's unstructured-grid volume mappers as peers: the X display they need, and their images
// against the CPU double-precision reference on scenes whose answer is known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>

#include "app/bench/vtk_peers.hpp"
#include "app/bench/x_display.hpp"
#include "renderer/volume/cpu/reference_frame.hpp"
#include "renderer/metrics/image_error.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

// Last: Xlib defines macros (None, Bool, Success) that clash with names in the headers above.
#include <X11/Xlib.h>

namespace prismoid {
namespace {

using bench::Peer;

// Sets an environment variable (or unsets it, for nullopt) for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, std::optional<std::string> value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    if (value) ::setenv(name, value->c_str(), 1);
    else ::unsetenv(name);
  }
  ~ScopedEnv() {
    if (old_) ::setenv(name_, old_->c_str(), 1);
    else ::unsetenv(name_);
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

bool process_exists(pid_t pid) { return ::kill(pid, 0) == 0 || errno != ESRCH; }

TEST(XDisplay, StartsAPrivateXvfbWhenDisplayIsUnsetAndStopsIt) {
  ScopedEnv no_display("DISPLAY", std::nullopt);
  pid_t pid = 0;
  {
    bench::XDisplay x;
    ASSERT_TRUE(x.started());
    pid = x.pid();
    ASSERT_GT(pid, 0);
    EXPECT_TRUE(process_exists(pid));
    ASSERT_NE(std::getenv("DISPLAY"), nullptr);
    EXPECT_EQ(std::string(std::getenv("DISPLAY")), x.name());
    EXPECT_EQ(x.name().front(), ':');
    Display* d = XOpenDisplay(nullptr);
    ASSERT_NE(d, nullptr) << "cannot open " << x.name();
    EXPECT_GE(XDisplayWidth(d, 0), 1280);
    EXPECT_GE(XDisplayHeight(d, 0), 1024);
    XCloseDisplay(d);
  }
  EXPECT_FALSE(process_exists(pid)) << "Xvfb " << pid << " still runs (or was not reaped) after the XDisplay ended";
  EXPECT_EQ(std::getenv("DISPLAY"), nullptr);
}

TEST(XDisplay, UsesTheDisplayDisplayNamesWithoutStartingAServer) {
  ScopedEnv no_display("DISPLAY", std::nullopt);
  bench::XDisplay outer;  // a display to point DISPLAY at
  ASSERT_TRUE(outer.started());
  bench::XDisplay inner;
  EXPECT_FALSE(inner.started());
  EXPECT_EQ(inner.pid(), 0);
  EXPECT_EQ(inner.name(), outer.name());
  EXPECT_EQ(std::string(std::getenv("DISPLAY")), outer.name());
}

TEST(XDisplay, ADisplayThatCannotBeOpenedIsAClearError) {
  ScopedEnv dead("DISPLAY", std::string(":4321"));  // no server there (Xvfb -displayfd counts up from 0)
  try {
    bench::XDisplay x;
    FAIL() << "an XDisplay opened :4321";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(":4321"), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::string(std::getenv("DISPLAY")), ":4321");  // left as the caller set it
}

TEST(XDisplay, MissingXvfbIsAClearError) {
  ScopedEnv no_display("DISPLAY", std::nullopt);
  const auto empty = std::filesystem::temp_directory_path() / "prismoid-no-xvfb-here";
  std::filesystem::create_directories(empty);
  ScopedEnv path("PATH", empty.string());
  try {
    bench::XDisplay x;
    FAIL() << "an XDisplay started without Xvfb on PATH";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("Xvfb"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("PATH"), std::string::npos) << e.what();
  }
  EXPECT_EQ(std::getenv("DISPLAY"), nullptr);
  std::filesystem::remove(empty);
}

// The peers draw through X: a private Xvfb when the suite runs without a display.
class VtkPeers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { display_ = std::make_unique<bench::XDisplay>(); }
  static void TearDownTestSuite() { display_.reset(); }
  static std::unique_ptr<bench::XDisplay> display_;
};
std::unique_ptr<bench::XDisplay> VtkPeers::display_;

// Odd sizes: the fitted cameras below look at the centre of the mesh, where the ball has a
// vertex; at an even size it projects exactly onto the ray caster's ray grid (rays at whole
// window coordinates, see ray_cast_ball), and VTK's ray caster then loses the absorption of the
// whole column of rays through it (a bright line: measured, and gone when the camera moves a
// fraction of a pixel sideways). The tests measure the peers in general position.
constexpr uint32_t kWidth = 129, kHeight = 97;

// A camera off every axis, so no silhouette edge lines up with the pixel grid.
Camera oblique_camera(const Bounds& b) {
  Camera c = fit_camera(b);
  const double distance = glm::length(c.eye - c.target);
  c.eye = c.target + distance * glm::normalize(glm::dvec3(0.45, 0.3, 1.0));
  return c;
}

volume::ResolveSettings transmittance_settings(glm::vec3 medium, glm::vec3 background) {
  volume::ResolveSettings s;
  s.quantity = volume::Quantity::Transmittance;
  s.medium = medium;
  s.background = background;
  return s;
}

// A box split into tetrahedra with a point scalar that varies, shown with one colour and
// constant extinction: the Color path (point scalars through a transfer function).
struct BoxScene {
  TetMesh mesh = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 3, [](const glm::dvec3& p) { return 4.0 + p.x + 2.0 * p.y; });
  volume::ResolveSettings resolve;
  BoxScene() {
    resolve.quantity = volume::Quantity::Color;
    resolve.background = {1.0f, 1.0f, 1.0f};
    auto& tf = resolve.transfer;
    tf.name = "constant";
    tf.color = {{0.0, glm::dvec3(0.0)}, {1.0, glm::dvec3(0.0)}};
    tf.opacity = {{0.0, 1.0}, {1.0, 1.0}};
    tf.range_lo = 1.0;
    tf.range_hi = 7.0;
    tf.density_scale = 10.0;
  }
};

// Pixels whose coverage (anything other than the background) differs between the peer and the
// reference, farther than `band` pixels (per axis) from the reference's silhouette. Covered:
// some channel more than `threshold` from the background.
size_t coverage_mismatches(const bench::PeerFrame& peer, const frame::OffscreenFrame& ref, glm::vec3 background, double threshold,
                           int band, size_t* covered_by_ref) {
  const uint32_t w = ref.width, h = ref.height;
  auto covered = [&](const std::vector<float>& display, uint32_t x, uint32_t y) {
    const size_t i = 4 * (size_t(y) * w + x);
    for (int k = 0; k < 3; ++k)
      if (std::abs(double(display[i + k]) - double(background[k])) > threshold) return true;
    return false;
  };
  size_t mismatches = 0;
  *covered_by_ref = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const bool r = covered(ref.display, x, y);
      *covered_by_ref += r;
      if (r == covered(peer.display, x, y)) continue;
      bool on_silhouette = false;  // a pixel within the band the reference sees differently
      for (int dy = -band; dy <= band; ++dy)
        for (int dx = -band; dx <= band; ++dx) {
          const int nx = int(x) + dx, ny = int(y) + dy;
          if (nx < 0 || ny < 0 || nx >= int(w) || ny >= int(h)) continue;
          on_silhouette |= covered(ref.display, uint32_t(nx), uint32_t(ny)) != r;
        }
      mismatches += !on_silhouette;
    }
  return mismatches;
}

// How far from the reference's silhouette a peer's coverage may differ, from where each puts its
// samples: projected tetrahedra rasterize at pixel centres like our rays (1: a pixel whose
// centre lies on an edge may go either way). The ray caster samples at pixel corners and its
// image is drawn as a texture stretched over the window, so pixel x shows samples around
// (x + 0.5)(W - 1)/W, up to one pixel from x + 0.5, blended bilinearly with the next one (2).
// ZSweep also truncates every projected vertex to whole pixels (3).
int coverage_band(Peer peer) {
  switch (peer) {
    case Peer::ProjectedTetrahedra: return 1;
    case Peer::RayCast: return 2;
    case Peer::ZSweep: return 3;
  }
  return 0;
}

// (a) Same camera, same projection: each peer covers the pixels the reference covers, up to its
// band at the silhouette. The medium is opaque enough (sigma 8 on a unit ball, 10 in the box)
// that any chord longer than 1e-3 shows by more than the threshold of 4/255.
TEST_F(VtkPeers, CoverTheReferencesPixelsUpToTheSilhouette) {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 2, 8.0);
  const auto ball_resolve = transmittance_settings({0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f});
  const BoxScene box;
  struct Scene {
    const char* label;
    const TetMesh& mesh;
    const volume::ResolveSettings& resolve;
  };
  for (const Scene& scene : {Scene{"ball:2 (cell extinction)", ball, ball_resolve}, Scene{"box (point scalars)", box.mesh, box.resolve}}) {
    const Camera camera = oblique_camera(bounds_of(scene.mesh));
    const auto ref = frame::render_reference(scene.mesh, camera, scene.resolve, {kWidth, kHeight});
    for (Peer peer : bench::kPeers) {
      SCOPED_TRACE(std::string(scene.label) + " " + std::string(bench::peer_name(peer)));
      const bench::PeerFrame f = bench::render_peer(peer, scene.mesh, camera, scene.resolve, kWidth, kHeight, 1);
      ASSERT_EQ(f.width, kWidth);
      ASSERT_EQ(f.height, kHeight);
      ASSERT_EQ(f.display.size(), size_t(kWidth) * kHeight * 4);
      ASSERT_EQ(f.frame_ms.size(), 1u);
      EXPECT_FALSE(f.gl_renderer.empty());
      size_t covered = 0;
      const size_t bad = coverage_mismatches(f, ref, scene.resolve.background, 4.0 / 255.0, coverage_band(peer), &covered);
      EXPECT_GT(covered, size_t(kWidth) * kHeight / 10);  // the scene fills a good part of the frame
      EXPECT_EQ(bad, 0u) << "pixels covered differently away from the silhouette";
    }
  }
}

// The ray-cast mapper's picture of a ball of constant extinction `sigma` (the medium colour over
// the background), from what vtkUnstructuredGridVolumeRayCastMapper, its Bunyk ray-cast function
// and vtkOpenGLRayCastImageDisplayHelper do:
// - the ray of image sample (X, Yv) (Yv counted from the bottom) runs through the continuous
//   window point (X, Yv): the integer corner, not the pixel centre, where we put (x + 0.5);
//   geometry there is exact (entry and exit depths from each face's screen-space plane);
// - each segment's length is measured between the entry and exit depths un-projected at NDC
//   (2X/(W-1) - 1, 2Yv/(H-1) - 1) instead: the chord along that other ray B between the same two
//   view depths, i.e. the true chord times cos(A)/cos(B) (cosines with the viewing axis);
// - the samples are drawn as a linearly filtered texture whose texel centres span the window
//   from the centre of the first pixel to the centre of the last, so window pixel x shows the
//   samples around (x + 0.5)(W - 1)/W, bilinearly weighted (likewise in y).
// Returns, per window pixel (our order: row 0 at the top), the displayed RGB, and per pixel the
// spread of the four samples blended into it (for the filter's weight rounding).
struct RayCastModel {
  std::vector<double> display;  // 3 per pixel
  std::vector<double> spread;   // 3 per pixel
};
RayCastModel ray_cast_ball(const TetMesh& ball, double sigma, const Camera& camera, glm::dvec3 medium, glm::dvec3 background,
                           uint32_t w, uint32_t h) {
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  std::vector<glm::dvec3> shown(size_t(w) * h);  // per sample, bottom row first
  for (uint32_t yv = 0; yv < h; ++yv)
    for (uint32_t x = 0; x < w; ++x) {
      const glm::dvec3 a = reference::ray_direction(camera, w, h, x, h - double(yv));
      const double ndc_x = 2.0 * x / (w - 1) - 1.0, ndc_y = 2.0 * yv / (h - 1) - 1.0;
      const glm::dvec3 b = reference::ray_direction(camera, w, h, (ndc_x + 1.0) / 2.0 * w, (1.0 - ndc_y) / 2.0 * h);
      double chord = 0.0;
      for (const auto& t : ball.tets) {
        const std::array<glm::dvec3, 4> v = {ball.points[t[0]], ball.points[t[1]], ball.points[t[2]], ball.points[t[3]]};
        chord += reference::ray_tetrahedron(v, camera.eye, a, 0.0, std::numeric_limits<double>::infinity()).length();
      }
      const double transmittance = std::exp(-sigma * chord * glm::dot(a, forward) / glm::dot(b, forward));
      shown[size_t(yv) * w + x] = medium * (1.0 - transmittance) + background * transmittance;
    }
  RayCastModel m;
  m.display.resize(size_t(w) * h * 3);
  m.spread.resize(m.display.size());
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const uint32_t yv = h - 1 - y;
      const double fx = (x + 0.5) * (w - 1.0) / w, fy = (yv + 0.5) * (h - 1.0) / h;
      const uint32_t x0 = uint32_t(fx), y0 = uint32_t(fy), x1 = std::min(x0 + 1, w - 1), y1 = std::min(y0 + 1, h - 1);
      const double ax = fx - x0, ay = fy - y0;
      const glm::dvec3 s00 = shown[size_t(y0) * w + x0], s01 = shown[size_t(y0) * w + x1], s10 = shown[size_t(y1) * w + x0],
                       s11 = shown[size_t(y1) * w + x1];
      const glm::dvec3 c = (1 - ay) * ((1 - ax) * s00 + ax * s01) + ay * ((1 - ax) * s10 + ax * s11);
      const glm::dvec3 spread = glm::max(glm::max(s00, s01), glm::max(s10, s11)) - glm::min(glm::min(s00, s01), glm::min(s10, s11));
      for (int k = 0; k < 3; ++k) {
        m.display[3 * (size_t(y) * w + x) + k] = c[k];
        m.spread[3 * (size_t(y) * w + x) + k] = spread[k];
      }
    }
  return m;
}

// (b) Accuracy where the model is closed form: a ball of constant extinction, the transmittance
// exp(-sigma chord) along each ray. sigma 1.5 keeps alpha below 0.99 on every chord (at most
// 1 - e^-3 = 0.95), so the ray caster's early stop at alpha 0.99 never cuts a ray short.
TEST_F(VtkPeers, RayCastMatchesTheClosedFormBallWithinItsQuantization) {
  const double sigma = 1.5;
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 2, sigma);
  const glm::vec3 medium(0.1f, 0.4f, 0.8f), background(0.9f, 0.85f, 0.3f);
  const auto resolve = transmittance_settings(medium, background);
  const Camera camera = oblique_camera(bounds_of(ball));
  const auto ref = frame::render_reference(ball, camera, resolve, {kWidth, kHeight});

  // The bound per channel: the ray caster stores premultiplied colour and alpha in 8 bits by
  // truncation (colour up to 1/255 low; alpha up to 1/255 low, letting up to background/255 more
  // of the background through); the background it is blended over was cleared to 8 bits (0.5/255);
  // the blend lands in an 8-bit pixel (0.5/255); the texture filter weighs the four samples with
  // 8-bit weights (llvmpipe), an error up to their spread/256. The linear ray integrator is
  // exact for constant extinction up to float rounding (1e-5 is generous).
  const bench::PeerFrame rc = bench::render_peer(Peer::RayCast, ball, camera, resolve, kWidth, kHeight, 1);
  const RayCastModel model = ray_cast_ball(ball, sigma, camera, medium, background, kWidth, kHeight);
  double worst = 0.0;
  size_t worst_at = 0;
  for (size_t p = 0; p < size_t(kWidth) * kHeight; ++p)
    for (int k = 0; k < 3; ++k) {
      const size_t i = 3 * p + k;
      const double bound = (1.0 + double(background[k]) + 0.5 + 0.5) / 255.0 + model.spread[i] / 256.0 + 1e-5;
      const double e = std::abs(double(rc.display[4 * p + k]) - model.display[i]);
      if (e / bound > worst) {
        worst = e / bound;
        worst_at = i;
      }
    }
  EXPECT_LE(worst, 1.0) << "largest error " << worst << " of its bound at pixel " << worst_at / 3 % kWidth << ","
                        << worst_at / 3 / kWidth << ": " << rc.display[worst_at / 3 * 4 + worst_at % 3] << " vs "
                        << model.display[worst_at];

  // Against the reference (rays through pixel centres): every peer is finite and much closer to
  // it than the background alone is.
  const std::vector<float> background_only = [&] {
    std::vector<float> b(size_t(kWidth) * kHeight * 4, 1.0f);
    for (size_t i = 0; i < b.size(); ++i)
      if (i % 4 != 3) b[i] = background[i % 4];
    return b;
  }();
  const double background_rmse = reference::image_error(background_only, ref.display, 1.0, 4, 3).rmse;
  ASSERT_GT(background_rmse, 0.05);
  for (Peer peer : bench::kPeers) {
    SCOPED_TRACE(std::string(bench::peer_name(peer)));
    const bench::PeerFrame f = peer == Peer::RayCast ? rc : bench::render_peer(peer, ball, camera, resolve, kWidth, kHeight, 0);
    if (peer != Peer::RayCast) {
      EXPECT_TRUE(f.frame_ms.empty());
    }
    const auto error = reference::image_error(f.display, ref.display, 1.0, 4, 3);
    EXPECT_EQ(error.non_finite, 0u);
    EXPECT_EQ(error.values, size_t(kWidth) * kHeight * 3);
    EXPECT_LT(error.rmse, 0.25 * background_rmse);
  }
}

// (c) Bad input is an InputError naming the problem, before any window opens.
TEST(VtkPeersInput, BadInputIsAnInputError) {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 1, 1.0);
  const Camera camera = fit_camera(bounds_of(ball));
  const auto transmittance = transmittance_settings({0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f});
  TetMesh empty;
  empty.name = "empty.vtu";
  for (Peer peer : bench::kPeers) {
    SCOPED_TRACE(std::string(bench::peer_name(peer)));
    try {
      bench::render_peer(peer, empty, camera, transmittance, 64, 48, 1);
      ADD_FAILURE() << "an empty mesh rendered";
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "empty.vtu");
      EXPECT_NE(std::string(e.what()).find("no cells"), std::string::npos) << e.what();
    }
    try {
      bench::render_peer(peer, ball, camera, transmittance, 0, 48, 1);
      ADD_FAILURE() << "a 0x48 image rendered";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("0x48"), std::string::npos) << e.what();
    }
    volume::ResolveSettings color = transmittance;
    color.quantity = volume::Quantity::Color;
    EXPECT_THROW(bench::render_peer(peer, ball, camera, color, 64, 48, 1), InputError) << "colour without scalars";
    volume::ResolveSettings iso = transmittance;
    iso.quantity = volume::Quantity::Isosurface;
    EXPECT_THROW(bench::render_peer(peer, ball, camera, iso, 64, 48, 1), InputError);
    Camera bad = camera;
    bad.target = bad.eye;
    EXPECT_THROW(bench::render_peer(peer, ball, bad, transmittance, 64, 48, 1), InputError);
  }
}

}  // namespace
}  // namespace prismoid
