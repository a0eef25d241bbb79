// The limits float32 sets on a volume frame (renderer/volume/float_limits), decided from the
// inputs: what is refused, with which limit, and what renders with a warning.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "renderer/volume/float_limits.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {
namespace {

using volume::check_float_limits;
using volume::float_facts;

// InputError from `f`, whose message contains every fragment.
template <typename F>
void expect_refused(F&& f, std::initializer_list<const char*> fragments) {
  try {
    f();
    ADD_FAILURE() << "not refused";
  } catch (const InputError& e) {
    for (const char* fragment : fragments) EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

volume::ResolveSettings quantity(volume::Quantity q) {
  volume::ResolveSettings s;
  s.quantity = q;
  return s;
}

TetMesh tall_cell(const glm::dvec3& base) {
  TetMesh mesh;
  mesh.name = "tall cell";
  mesh.points = {base, base + glm::dvec3(1, 0, 0), base + glm::dvec3(0, 1, 0), base + glm::dvec3(0, 0, 1e6)};
  mesh.tets = {{0, 1, 2, 3}};
  mesh.cell_extinction = {1.0};
  return mesh;
}

Camera beside(const glm::dvec3& base) {
  Camera camera;
  camera.eye = base + glm::dvec3(0.2, -5.0, 0.5);
  camera.target = base + glm::dvec3(0.2, 0.0, 0.5);
  camera.up = {0.0, 0.0, 1.0};
  camera.near_distance = 0.01;
  return camera;
}

TEST(FloatLimits, OpticalDepthBeyondFloatIsRefusedWithItsLimitAndTransmittanceIsNot) {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 2, 1e300);
  const auto facts = float_facts(ball);
  const Camera camera = fit_camera(facts.bounds);
  for (bool gpu : {true, false})
    expect_refused([&] { check_float_limits(facts, camera, 64, 64, quantity(volume::Quantity::OpticalDepth), gpu); },
                   {"ball", "optical depths up to 3.46e+300", "exceed 5.19e+33", "density-scale", "quantity transmittance"});
  EXPECT_NO_THROW(check_float_limits(facts, camera, 64, 64, quantity(volume::Quantity::Transmittance)));
  // The largest extinction whose optical depth float still holds, with the margin, over the
  // ball's diagonal (2 sqrt 3 of its bounds): just below is accepted.
  const double limit = volume::kSumMargin * volume::kFloatMax / facts.diagonal;
  EXPECT_DOUBLE_EQ(volume::extinction_cap(facts.diagonal), limit);
  EXPECT_NO_THROW(check_float_limits(float_facts(make_ball_mesh(glm::dvec3(0.0), 1.0, 2, 0.99 * limit)), camera, 64, 64,
                                     quantity(volume::Quantity::OpticalDepth)));
}

TEST(FloatLimits, TransferRangeMapsThroughScaleAndOffsetAndRefusesWhatFloatCannotHold) {
  volume::TransferFunction tf = volume::preset("viridis");
  tf.range_lo = -1e300;
  tf.range_hi = 1e300;
  const volume::ScalarMapping m = volume::scalar_mapping(tf);
  EXPECT_EQ(float(m.scale), 0.0f);  // 5e-301: below float, and negligible for any data
  EXPECT_EQ(float(m.offset), 0.5f);
  TetMesh mesh = make_default_volume();  // scalars in [0, ~3]
  const auto facts = float_facts(mesh);
  volume::ResolveSettings color = quantity(volume::Quantity::Color);
  color.transfer = tf;
  const Camera camera = fit_camera(facts.bounds);
  EXPECT_TRUE(check_float_limits(facts, camera, 64, 64, color).warnings.empty());
  // A range so narrow the data map beyond float; one so wide that 1 / width is no normal float
  // yet still moves the data's x: both refused.
  color.transfer.range_lo = 0.0;
  color.transfer.range_hi = 1e-40;
  expect_refused([&] { check_float_limits(facts, camera, 64, 64, color); }, {"tf-range", "beyond float32's range"});
  mesh.point_scalars.assign(mesh.points.size(), 1e37);
  color.transfer.range_lo = -1e38;
  color.transfer.range_hi = 1e38;
  expect_refused([&] { check_float_limits(float_facts(mesh), camera, 64, 64, color); }, {"tf-range", "smallest normal"});
  // Far from zero and narrow: refused by nothing, but placed only to float's precision: a warning.
  mesh.point_scalars.assign(mesh.points.size(), 1e6);
  color.transfer.range_lo = 1e6;
  color.transfer.range_hi = 1e6 + 1.0;
  const auto check = check_float_limits(float_facts(mesh), camera, 64, 64, color);
  ASSERT_EQ(check.warnings.size(), 1u);
  EXPECT_NE(check.warnings[0].find("tf-range"), std::string::npos) << check.warnings[0];
  mesh.point_scalars.assign(mesh.points.size(), 1e39);
  expect_refused([&] { check_float_limits(float_facts(mesh), camera, 64, 64, color); }, {"scalar values up to 1e+39"});
}

TEST(FloatLimits, CameraBeyondFloatsRangeIsRefused) {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 1, 1.0);
  const auto facts = float_facts(ball);
  Camera far = fit_camera(facts.bounds);
  far.eye = {0.0, 0.0, 1e31};
  expect_refused([&] { check_float_limits(facts, far, 64, 64, quantity(volume::Quantity::Transmittance)); }, {"camera", "2^100"});
  Camera narrow = fit_camera(facts.bounds);
  narrow.fovy_degrees = 1e-20;
  expect_refused([&] { check_float_limits(facts, narrow, 64, 64, quantity(volume::Quantity::Transmittance)); },
                 {"fovy 1e-20", "2^60"});
  Camera close = fit_camera(facts.bounds);
  close.near_distance = 1e-25;
  expect_refused([&] { check_float_limits(facts, close, 64, 64, quantity(volume::Quantity::Transmittance)); },
                 {"near 1e-25", "raise near"});
  // fovy 1e-6 is fine: the frame is drawn relative to each cell.
  EXPECT_TRUE(check_float_limits(facts, fit_camera(facts.bounds, 1e-6), 64, 64, quantity(volume::Quantity::Transmittance))
                  .warnings.empty());
}

TEST(FloatLimits, PositionsRoundedBeyondTheRasterizersSnappingWarnWithTheirSize) {
  // An ordinary view: float's rounding is far below a pixel, by the bound alone.
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.3, -0.2, 0.1), 1.0, 1, 1.0);
  EXPECT_TRUE(check_float_limits(float_facts(ball), fit_camera(bounds_of(ball)), 800, 600, quantity(volume::Quantity::OpticalDepth))
                  .warnings.empty());
  // A cell 10^6 tall seen from 5 units: the GPU's positions are relative to its centre, 5e5
  // away, where floats are 1/32 apart. With the eye off that grid the camera's translation
  // rounds by up to 1/64 world units, a good part of a pixel at depth 5.
  const glm::dvec3 base(0.1234567, 0.3, 0.77777);
  const TetMesh off_grid = tall_cell(base);
  Camera camera = beside(base);
  camera.eye = {0.32, -4.7, 1.27};
  camera.target = {0.32, 0.3, 1.27};
  for (const std::vector<glm::dvec3>* points : {static_cast<const std::vector<glm::dvec3>*>(nullptr), &off_grid.points}) {
    const auto check =
        check_float_limits(float_facts(off_grid), camera, 64, 64, quantity(volume::Quantity::OpticalDepth), true, points);
    ASSERT_EQ(check.warnings.size(), 1u);
    EXPECT_NE(check.warnings[0].find("world units across the view"), std::string::npos) << check.warnings[0];
    EXPECT_NE(check.warnings[0].find("pixels at depth 5"), std::string::npos) << check.warnings[0];
  }
  // On the grid (the corners and the eye exact in float there): the bound alone cannot tell
  // (the transform's products might round), the points measured say float is exact.
  const TetMesh on_grid = tall_cell(glm::dvec3(0.0));
  const auto bound = check_float_limits(float_facts(on_grid), beside(glm::dvec3(0.0)), 64, 64, quantity(volume::Quantity::OpticalDepth));
  EXPECT_EQ(bound.warnings.size(), 1u);
  EXPECT_TRUE(check_float_limits(float_facts(on_grid), beside(glm::dvec3(0.0)), 64, 64, quantity(volume::Quantity::OpticalDepth), true,
                                 &on_grid.points)
                  .warnings.empty());
}

}  // namespace
}  // namespace prismoid
