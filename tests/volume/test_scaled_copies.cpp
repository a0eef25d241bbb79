// Scaled copies of one scene render alike: a 6^3 grid of tetrahedra with a smooth point field,
// its coordinates multiplied by S and moved off the world origin by 2S, its extinction per
// length divided by S (the same optical thickness), seen by the same camera scaled with it.
// Dimensionless answers (colour, optical depth) do not depend on S; the GPU draws in units
// of the data's size (frame/frame_units.hpp), so both backends must match the CPU reference
// within the tolerances of S = 1 at every S from 1e-90 to 1e90 (colour; optical depth to 1e+-30,
// where this comparison's own tolerance derivation, in world units, still fits double). Before those units, the mesh
// backend went wrong from S = 3e10 and below 1e-12 (lengths to the fourth power leave float),
// the compute backend from 1e15. Data spanning beyond that range are refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <cstdio>
#include <string>

#include "renderer/frame/frame_renderer.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"
#include "volume/color_comparison.hpp"
#include "volume/interval_comparison.hpp"

namespace prismoid {
namespace {

class ScaledCopyTest : public test::IntervalShadingTest {};

const glm::dvec3 kOffset(2.0, -1.0, 0.5);

double field(const glm::dvec3& p) { return std::sin(3.0 * p.x) * std::cos(2.0 * p.y) + p.z; }

TetMesh scaled_grid(double s) {
  TetMesh m = make_box_mesh(glm::dvec3(0.0), glm::dvec3(1.0), 6, [](const glm::dvec3& p) { return 1.5 + p.x; });
  m.name = "grid scaled by " + std::to_string(s);
  m.point_scalars.clear();
  for (glm::dvec3& p : m.points) {
    m.point_scalars.push_back(field(p));
    p = (p + kOffset) * s;
  }
  for (double& sigma : m.cell_extinction) sigma /= s;
  for (double& sigma : m.point_extinction) sigma /= s;
  return m;
}

Camera scaled_camera(double s) {
  Camera c;
  c.target = (glm::dvec3(0.5) + kOffset) * s;
  c.eye = c.target + glm::dvec3(1.1, 0.8, 1.9) * s;
  c.up = {0.0, 1.0, 0.0};
  c.fovy_degrees = 45.0;
  c.near_distance = 0.05 * s;
  return c;
}

volume::TransferFunction scaled_tf(double s) {
  volume::TransferFunction tf = volume::preset("cool-to-warm");
  tf.range_lo = -1.0;
  tf.range_hi = 2.0;
  tf.opacity = {{0.0, 0.2}, {0.5, 0.9}, {1.0, 0.5}};
  tf.density_scale = 2.0 / s;
  return tf;
}

constexpr double kScales[] = {1e-90, 1e-30, 1e-12, 1e-6, 1.0, 3e10, 1e15, 3e19, 1e20, 1e30, 1e90};

TEST_P(ScaledCopyTest, ColourMatchesTheReferenceAtEveryScale) {
  const uint32_t w = 48, h = 36;
  size_t covered_at_one = 0;
  for (double s : kScales) {
    const TetMesh mesh = scaled_grid(s);
    const test::ColorComparison c =
        test::ColorTest::compare(mesh, scaled_tf(s), scaled_camera(s), w, h, frame::Ordering::Exact, 0, backend());
    if (s == 1.0) covered_at_one = c.covered;
    EXPECT_EQ(c.failures, 0u) << "S = " << s << ": " << c.first_failure << " (max error " << c.max_error << ")";
    EXPECT_GT(c.covered, size_t(w) * h / 4) << "S = " << s;
    EXPECT_TRUE(c.report.warnings.empty()) << "S = " << s << ": " << c.report.warnings.front();
    std::printf("S = %g: colour max error %.3g, RMSE %.3g, %zu pixels covered\n", s, c.max_error, c.rmse, c.covered);
  }
  EXPECT_GT(covered_at_one, 0u);
}

TEST_P(ScaledCopyTest, OpticalDepthMatchesTheReferenceAtEveryScale) {
  const uint32_t w = 48, h = 36;
  for (double s : kScales) {
    if (std::abs(std::log10(s)) > 30.0) continue;
    const Comparison c = compare(scaled_grid(s), scaled_camera(s), w, h);
    EXPECT_EQ(c.failures, 0u) << "S = " << s << ": " << c.first_failure;
    EXPECT_GT(c.covered, size_t(w) * h / 4) << "S = " << s;
    std::printf("S = %g: optical depth max error %.3g (worst pixel at %.2f of its tolerance)\n", s, c.max_error,
                c.max_relative_to_tolerance);
  }
}

PRISMOID_ON_BOTH_BACKENDS(ScaledCopyTest);

// The default camera frames data of any size alike (it once put tiny data a fixed 1e-12 away
// from filling the view, and data below that rendered blank).
TEST(ScaledCopies, TheDefaultCameraFramesEveryScaleAlike) {
  const Camera one = fit_camera(bounds_of(scaled_grid(1.0)));
  const double at_one = glm::length(one.eye - one.target) / (bounds_of(scaled_grid(1.0)).radius());
  for (double s : {1e-90, 1e-13, 1e-12, 1e20, 1e90}) {
    const Bounds b = bounds_of(scaled_grid(s));
    const Camera c = fit_camera(b);
    EXPECT_NEAR(glm::length(c.eye - c.target) / b.radius(), at_one, 1e-9 * at_one) << "S = " << s;
    EXPECT_NEAR(c.near_distance / b.radius(), one.near_distance / bounds_of(scaled_grid(1.0)).radius(), 1e-9) << "S = " << s;
  }
}

TEST(ScaledCopies, DataSpanningBeyondDoublesCellGeometryAreRefusedByName) {
  for (double s : {1e95, 1e-95}) {
    const TetMesh mesh = scaled_grid(s);
    try {
      validate(mesh);
      ADD_FAILURE() << "S = " << s << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(mesh.name), std::string::npos) << what;
      EXPECT_NE(what.find("rescale the coordinates"), std::string::npos) << what;
    }
  }
  EXPECT_NO_THROW(validate(scaled_grid(1e90)));
  EXPECT_NO_THROW(validate(scaled_grid(1e-90)));
}

}  // namespace
}  // namespace prismoid
