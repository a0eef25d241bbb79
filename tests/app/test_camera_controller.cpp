// The viewer's camera without a window: what each gesture must preserve, and the camera line
// that takes a view from the window to `prismoid render`.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "app/viewer/camera_controller.hpp"
#include "app/viewer/camera_line.hpp"
#include "app/viewer/mouse_bindings.hpp"
#include "scene/input_error.hpp"

namespace prismoid {
namespace {

using app::AxisView;
using app::CameraController;

// An off-centre, non-cubic box, so a bug that assumes the origin or a cube shows.
const Bounds kBounds{{-1.0, 2.0, 0.5}, {3.0, 3.0, 4.5}};
const glm::dvec2 kViewport{800.0, 600.0};

// Rotations and translations in double: the quantities they preserve change by a few ulps of
// the coordinates (about 1e-15 here); 1e-12 leaves room and still catches any real error.
constexpr double kTight = 1e-12;

TEST(CameraController, RotationKeepsTheDistanceToTheTarget) {
  CameraController c(kBounds);
  const glm::dvec3 target = c.camera().target;
  const double before = glm::distance(c.camera().eye, target);
  for (const glm::dvec2 drag : {glm::dvec2(37, 0), glm::dvec2(0, -81), glm::dvec2(-250, 143), glm::dvec2(600, 600)}) {
    const glm::dvec3 eye_before = c.camera().eye;
    c.rotate(drag, kViewport);
    EXPECT_NEAR(glm::distance(c.camera().eye, target), before, kTight * before);
    EXPECT_EQ(c.camera().target, target);
    EXPECT_GT(glm::distance(c.camera().eye, eye_before), 0.0) << "the drag moved nothing";
    // Up stays a unit vector orthogonal to the view direction (a valid camera).
    const glm::dvec3 forward = glm::normalize(c.camera().target - c.camera().eye);
    EXPECT_NEAR(glm::length(c.camera().up), 1.0, kTight);
    EXPECT_NEAR(glm::dot(c.camera().up, forward), 0.0, kTight);
  }
}

TEST(CameraController, DraggingAcrossTheViewportHeightTurnsHalfAround) {
  CameraController c(kBounds);
  const glm::dvec3 before = glm::normalize(c.camera().eye - c.camera().target);
  c.rotate({kViewport.y, 0.0}, kViewport);
  const glm::dvec3 after = glm::normalize(c.camera().eye - c.camera().target);
  EXPECT_NEAR(glm::dot(before, after), -1.0, kTight);
}

TEST(CameraController, PanMovesEyeAndTargetEqually) {
  CameraController c(kBounds);
  c.rotate({120, -40}, kViewport);
  const Camera before = c.camera();
  c.pan({55, -23}, kViewport);
  const glm::dvec3 eye_shift = c.camera().eye - before.eye, target_shift = c.camera().target - before.target;
  EXPECT_GT(glm::length(eye_shift), 0.0);
  EXPECT_NEAR(glm::distance(eye_shift, target_shift), 0.0, kTight);
  // The shift lies in the image plane: the view direction is unchanged.
  EXPECT_NEAR(glm::dot(eye_shift, glm::normalize(before.target - before.eye)), 0.0, kTight);
  // A drag of the viewport's height moves by the height of the view at the target's distance.
  CameraController d(kBounds);
  const Camera start = d.camera();
  d.pan({0.0, kViewport.y}, kViewport);
  const double distance = glm::distance(start.eye, start.target);
  const double height = 2.0 * distance * std::tan(glm::radians(start.fovy_degrees) / 2.0);
  EXPECT_NEAR(glm::distance(d.camera().target, start.target), height, kTight * height);
}

TEST(CameraController, ZoomMovesAlongTheViewDirectionOnly) {
  CameraController c(kBounds);
  const Camera before = c.camera();
  c.zoom(3.0);
  EXPECT_EQ(c.camera().target, before.target);
  const double ratio = glm::distance(c.camera().eye, before.target) / glm::distance(before.eye, before.target);
  EXPECT_NEAR(ratio, std::pow(0.9, 3.0), kTight);
  EXPECT_NEAR(glm::length(glm::cross(glm::normalize(c.camera().eye - before.target), glm::normalize(before.eye - before.target))), 0.0, kTight);
}

// Zooming or panning away stops kFarthest radii from the data, looking the same way, for data of
// any size (zooming out 700 steps once took the eye 1e32 away and ended the window).
TEST(CameraController, ZoomingAndPanningAwayStopAtTheFarthestReach) {
  for (double s : {1e-20, 1.0, 1e20}) {
    const Bounds b{kBounds.min * s, kBounds.max * s};
    const double reach = CameraController::kFarthest * b.radius();
    CameraController c(b);
    const glm::dvec3 direction = glm::normalize(c.camera().target - c.camera().eye);
    c.zoom(-700.0);
    EXPECT_LE(glm::distance(c.camera().eye, b.center()), reach * (1.0 + 1e-12)) << "S = " << s;
    EXPECT_GT(glm::distance(c.camera().eye, b.center()), 0.5 * reach) << "S = " << s;
    EXPECT_NEAR(glm::dot(glm::normalize(c.camera().target - c.camera().eye), direction), 1.0, kTight) << "S = " << s;
    EXPECT_NEAR(glm::dot(glm::normalize(b.center() - c.camera().eye), direction), 1.0, 1e-9) << "the data left the view";
    for (int i = 0; i < 100; ++i) c.pan({3e7, -2e7}, kViewport);
    EXPECT_LE(glm::distance(c.camera().eye, b.center()), reach * (1.0 + 1e-12)) << "S = " << s;
    EXPECT_GT(c.camera().near_distance, 0.0);
    // Zooming back in still works from there.
    c.zoom(700.0);
    EXPECT_LT(glm::distance(c.camera().eye, c.camera().target), b.radius()) << "S = " << s;
  }
}

// The bounding sphere lies inside the view cone of the narrower field of view, with a margin.
void expect_frames_bounds(const Camera& c, const Bounds& b, double aspect) {
  const glm::dvec3 forward = glm::normalize(c.target - c.eye);
  EXPECT_NEAR(glm::distance(c.target, b.center()), 0.0, kTight);
  const double half_y = glm::radians(c.fovy_degrees) / 2.0;
  const double half = std::min(half_y, std::atan(std::tan(half_y) * aspect));
  const double distance = glm::distance(c.eye, b.center());
  EXPECT_LE(b.radius(), distance * std::sin(half)) << "the bounding sphere pokes out of the view";
  EXPECT_GE(b.radius(), 0.9 * distance * std::sin(half)) << "the data fills less than 90% of the view";
  EXPECT_GT(c.near_distance, 0.0);
  EXPECT_LE(c.near_distance, distance - b.radius()) << "the near plane cuts the data";
  EXPECT_NEAR(glm::dot(forward, glm::normalize(b.center() - c.eye)), 1.0, kTight);
}

TEST(CameraController, ResetFramesTheBoundsFromTheCurrentDirection) {
  for (const double aspect : {1.6, 0.5}) {
    CameraController c(kBounds);
    c.rotate({200, 75}, kViewport);
    c.pan({300, 100}, kViewport);
    c.zoom(-7.0);
    const glm::dvec3 direction = glm::normalize(c.camera().target - c.camera().eye);
    c.reset(aspect);
    expect_frames_bounds(c.camera(), kBounds, aspect);
    EXPECT_NEAR(glm::dot(glm::normalize(c.camera().target - c.camera().eye), direction), 1.0, kTight);
  }
}

TEST(CameraController, AxisViewsLookAlongTheirAxisWithParaViewsUp) {
  struct Case { AxisView view; glm::dvec3 look, up; };
  const Case cases[] = {{AxisView::PlusX, {1, 0, 0}, {0, 0, 1}},  {AxisView::MinusX, {-1, 0, 0}, {0, 0, 1}},
                        {AxisView::PlusY, {0, 1, 0}, {0, 0, 1}},  {AxisView::MinusY, {0, -1, 0}, {0, 0, 1}},
                        {AxisView::PlusZ, {0, 0, 1}, {0, 1, 0}},  {AxisView::MinusZ, {0, 0, -1}, {0, 1, 0}}};
  for (const Case& k : cases) {
    CameraController c(kBounds);
    c.rotate({91, 33}, kViewport);
    c.axis_view(k.view, 1.0);
    const Camera& cam = c.camera();
    EXPECT_NEAR(glm::distance(glm::normalize(cam.target - cam.eye), k.look), 0.0, kTight) << app::axis_view_name(k.view);
    EXPECT_NEAR(glm::distance(cam.up, k.up), 0.0, kTight) << app::axis_view_name(k.view);
    expect_frames_bounds(cam, kBounds, 1.0);
  }
}

TEST(CameraController, FlyingIntoTheVolumeKeepsAValidNearPlane) {
  CameraController c(kBounds);
  c.set_flying(true);
  const double start = glm::distance(c.camera().eye, kBounds.center());
  // Forward for as long as it takes to reach the centre: the eye ends inside the bounds.
  c.fly_move({0, 0, 1}, start / c.fly_speed());
  const Camera& cam = c.camera();
  EXPECT_NEAR(glm::distance(cam.eye, kBounds.center()), 0.0, 1e-9 * start);
  EXPECT_GT(cam.near_distance, 0.0);
  EXPECT_LE(cam.near_distance, 1e-3 * kBounds.radius()) << "inside the data the near plane must be tiny";
  EXPECT_NO_THROW(validate(cam));
  // Looking around turns the view about the eye, which stays put.
  const glm::dvec3 eye = cam.eye;
  c.fly_look({100, -50}, kViewport);
  EXPECT_EQ(c.camera().eye, eye);
  // Moving right keeps the height and depth of the eye in camera axes.
  const Camera before = c.camera();
  c.fly_move({1, 0, 0}, 0.5);
  const glm::dvec3 shift = c.camera().eye - before.eye;
  EXPECT_NEAR(glm::length(shift), 0.5 * c.fly_speed(), kTight * c.fly_speed());
  EXPECT_NEAR(glm::dot(shift, before.up), 0.0, kTight);
}

TEST(CameraController, NearPlaneIsHalfTheDistanceToTheBoundsOutsideThem) {
  const glm::dvec3 eye = kBounds.max + glm::dvec3(0.0, 0.0, 2.0);
  EXPECT_DOUBLE_EQ(app::near_distance_for(eye, kBounds), 1.0);
}

// ParaView's mouse bindings: left rotates, shift+left and middle pan, right zooms; in fly mode
// left looks around.
TEST(MouseBindings, DragsMakeParaViewsGestures) {
  using app::DragGesture;
  using B = app::MouseButtons;
  EXPECT_EQ(app::drag_gesture(B{true, false, false, false}, false), DragGesture::Rotate);
  EXPECT_EQ(app::drag_gesture(B{true, false, false, true}, false), DragGesture::Pan);
  EXPECT_EQ(app::drag_gesture(B{false, true, false, false}, false), DragGesture::Pan);
  EXPECT_EQ(app::drag_gesture(B{false, false, true, false}, false), DragGesture::Zoom);
  EXPECT_EQ(app::drag_gesture(B{true, false, false, false}, true), DragGesture::Look);
  EXPECT_FALSE(app::drag_gesture(B{}, false).has_value());
  // A right drag upwards (negative screen y) brings the eye closer, 20 pixels a wheel step.
  CameraController c(kBounds);
  const double before = glm::distance(c.camera().eye, c.camera().target);
  app::apply_drag(c, DragGesture::Zoom, {0.0, -40.0}, kViewport);
  EXPECT_NEAR(glm::distance(c.camera().eye, c.camera().target), before * 0.81, kTight * before);
}

// The line the window prints and copies parses back through render's own option parser to
// the same camera: %.17g makes every double exact, so 1e-9 is a loose bound.
TEST(CameraLine, ParsesBackThroughTheCliToTheSameCamera) {
  CameraController c(kBounds);
  c.rotate({123.4, -56.7}, kViewport);
  c.pan({7.1, 3.3}, kViewport);
  c.zoom(2.5);
  const Camera original = c.camera();
  const std::string line = app::camera_line(original);
  EXPECT_EQ(line.rfind("--eye ", 0), 0u) << line;
  const Camera parsed = app::camera_from_line(line, kBounds);
  EXPECT_NEAR(glm::distance(parsed.eye, original.eye), 0.0, 1e-9);
  EXPECT_NEAR(glm::distance(parsed.target, original.target), 0.0, 1e-9);
  EXPECT_NEAR(glm::distance(parsed.up, original.up), 0.0, 1e-9);
  EXPECT_NEAR(parsed.fovy_degrees, original.fovy_degrees, 1e-9);
  EXPECT_NEAR(parsed.near_distance, original.near_distance, 1e-9);
}

TEST(CameraLine, BadLinesNameTheOption) {
  try {
    app::camera_from_line("--eye 1,2 --target 0,0,0", kBounds);
    FAIL() << "accepted a two-component eye";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--eye"), std::string::npos) << e.what();
  }
  EXPECT_THROW(app::camera_from_line("--eye 0,0,0 --target 0,0,0", kBounds), InputError);
  EXPECT_THROW(app::camera_from_line("--zoom 3", kBounds), InputError);
}

}  // namespace
}  // namespace prismoid
