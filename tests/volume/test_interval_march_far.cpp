// Marching far from the world origin: the mesh is uploaded relative to its bounds' centre, so
// a volume at 1e5 must render as well as the same volume at the origin. Each test states
// where its tolerance comes from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/analytic_march.hpp"
#include "scene/tet_mesh.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

constexpr double kUlp = 0x1p-24;

// The "blobs" field and its 4^3 Kuhn box, both moved by `offset` (the blobs' centres and the
// box's points, in double): the same volume, anywhere.
volume::AnalyticField blobs_at(const glm::dvec3& offset) {
  volume::AnalyticField field = volume::field_from_name("blobs");
  for (glm::dvec4& b : field.params) b = glm::dvec4(glm::dvec3(b) + offset, b.w);
  return field;
}

TetMesh box_at(const glm::dvec3& offset) {
  TetMesh mesh = volume::make_field_mesh(volume::field_from_name("blobs"), 4);
  for (glm::dvec3& p : mesh.points) p += offset;  // scalars and extinction move with the field
  return mesh;
}

class IntervalMarchFarTest : public test::GpuTest, public test::OnBackend {};

// Optical depth of the blobs at the origin and at (1e5, -1e5, 1e5) + small, seen from the
// same relative eye, each against its double-precision reference. The tolerance is the same
// for both: nothing in it grows with the distance from the world origin.
//  - the midpoint rule, L S^2 / 24 * second_derivative_bound (L <= the box's diagonal);
//  - rasterizer snapping: the fragment samples the exact pixel ray, but its interval's ends
//    come from proxies whose vertices snap by up to 2 * 2^-subPixelPrecisionBits pixel; twice
//    the largest change of the reference when the ray moves that far (8 directions);
//  - float: n + 16 roundings of the running sum (relative), and the sample's position carries
//    2^-20 of the eye's distance to the mesh plus the ray's length (8 roundings, doubled),
//    times |grad f| <= sum 1 / (w sqrt(e)), over the ray's length.
// Before fields were moved into the mesh frame (volume::translated) the far image erred by
// 0.0155 (100x the image at the origin, 6x this tolerance): the sample's world position
// (~1e5, float spacing 2^-7 = 0.008) and the blobs' centres (rounded by 0.004) moved the
// field by up to |grad f| * 0.012.
TEST_P(IntervalMarchFarTest, BlobsFarFromOriginMatchReferenceAsAtOrigin) {
  const uint32_t w = 40, h = 40;
  const double step = 0.01, diagonal = 2.0 * std::sqrt(3.0);
  const volume::AnalyticField at_origin = volume::field_from_name("blobs");
  double grad_bound = 0.0;
  for (const glm::dvec4& b : at_origin.params) grad_bound += 1.0 / (b.w * std::sqrt(M_E));
  const glm::dvec3 relative_eye(0.9, 0.7, 3.6);
  const double step_bound = diagonal * step * step / 24.0 * volume::second_derivative_bound(at_origin);
  const double reach = glm::length(relative_eye) + diagonal;
  const double n = std::ceil(diagonal / step) + 12.0;  // steps, plus one per cell crossed (<= 12)
  double worst_far = 0.0;
  for (const glm::dvec3 offset : {glm::dvec3(0.0), glm::dvec3(1e5 + 0.3, -1e5 + 0.1, 1e5 - 0.2)}) {
    const volume::AnalyticField field = blobs_at(offset);
    const TetMesh mesh = box_at(offset);
    Camera camera;
    camera.eye = offset + relative_eye;
    camera.target = offset;
    camera.fovy_degrees = 40.0;
    camera.near_distance = 0.05;
    frame::FrameRenderer renderer(device(), mesh);
    frame::FrameSettings settings = settings_on_backend();
    settings.resolve.quantity = volume::Quantity::OpticalDepth;
    settings.resolve.march.enabled = true;
    settings.resolve.march.field = field;
    settings.resolve.march.step = step;
    settings.ordering = frame::Ordering::MeshOrder;
    const auto gpu = renderer.render_offscreen(camera, settings, {w, h});
    const auto ref = reference::field_optical_depth_image(mesh, field, 1.0, camera, w, h);
    const double radius = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
    std::vector<double> snap(ref.size(), 0.0);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy) continue;
        const auto moved = reference::field_optical_depth_image(mesh, field, 1.0, camera, w, h, 0.01, dx * radius, dy * radius);
        for (size_t i = 0; i < ref.size(); ++i) snap[i] = std::max(snap[i], 2.0 * std::abs(moved[i] - ref[i]));
      }
    double max_err = 0.0, worst = 0.0;
    size_t failures = 0, covered = 0;
    for (size_t i = 0; i < ref.size(); ++i) {
      const double float_tol = ref[i] * (n + 16.0) * 2.0 * kUlp + grad_bound * 8.0 * kUlp * reach * diagonal;
      const double tol = step_bound + snap[i] + float_tol;
      const double err = std::abs(double(gpu.quantity[i]) - ref[i]);
      if (ref[i] > 0.0) ++covered;
      max_err = std::max(max_err, err);
      worst = std::max(worst, err / tol);
      if (err > tol) ++failures;
    }
    std::printf("offset %.0f: max error %.3g, worst pixel at %.3f of its tolerance, %zu pixels beyond it\n", offset.x, max_err,
                worst, failures);
    EXPECT_GT(covered, 300u);
    EXPECT_EQ(failures, 0u) << "offset " << offset.x;
    if (offset.x != 0.0) worst_far = worst;
  }
  ::testing::Test::RecordProperty("far_worst_over_tolerance", std::to_string(worst_far));
}

PRISMOID_ON_BOTH_BACKENDS(IntervalMarchFarTest);

}  // namespace
}  // namespace prismoid
