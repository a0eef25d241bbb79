#include "app/viewer/camera_controller.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/trigonometric.hpp>

namespace prismoid::app {

namespace {

// v turned by `angle` radians about the unit `axis` (Rodrigues' formula).
glm::dvec3 turn(const glm::dvec3& v, double angle, const glm::dvec3& axis) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + glm::cross(axis, v) * s + axis * glm::dot(axis, v) * (1.0 - c);
}

glm::dvec3 forward_of(const Camera& c) { return glm::normalize(c.target - c.eye); }
glm::dvec3 right_of(const Camera& c) { return glm::normalize(glm::cross(forward_of(c), c.up)); }

// The scene's own length: its bounds' radius (data of 1e-20 are handled as data of 1e20), or 1
// for bounds of a single point.
double scale_of(const Bounds& bounds) {
  const double r = bounds.radius();
  return r > 0.0 && std::isfinite(r) ? r : 1.0;
}

// The distance at which a sphere of `radius` fits the narrower field of view, with a margin.
double fit_distance(double radius, double fovy_degrees, double aspect) {
  const double half_y = glm::radians(fovy_degrees) * 0.5;
  const double half_x = std::atan(std::tan(half_y) * std::max(aspect, 1e-6));
  return radius / std::sin(std::min(half_x, half_y)) * 1.05;
}

}  // namespace

const char* axis_view_name(AxisView view) {
  switch (view) {
    case AxisView::PlusX: return "+X";
    case AxisView::MinusX: return "-X";
    case AxisView::PlusY: return "+Y";
    case AxisView::MinusY: return "-Y";
    case AxisView::PlusZ: return "+Z";
    case AxisView::MinusZ: return "-Z";
  }
  return "?";
}

double near_distance_for(const glm::dvec3& eye, const Bounds& bounds) {
  const glm::dvec3 outside = glm::max(bounds.min - eye, glm::max(glm::dvec3(0.0), eye - bounds.max));
  const double to_bounds = glm::length(outside);
  const double floor = scale_of(bounds) * 1e-4;
  return std::max(0.5 * to_bounds, floor);
}

CameraController::CameraController(const Bounds& bounds) : bounds_(bounds), camera_(fit_camera(bounds)) { keep_valid(); }

CameraController::CameraController(const Bounds& bounds, const Camera& camera) : bounds_(bounds), camera_(camera) { keep_valid(); }

void CameraController::set_camera(const Camera& camera) {
  camera_ = camera;
  keep_valid();
}

void CameraController::keep_valid() {
  const glm::dvec3 f = forward_of(camera_);
  glm::dvec3 up = camera_.up - glm::dot(camera_.up, f) * f;
  if (glm::length(up) < 1e-9) up = std::abs(f.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
  camera_.up = glm::normalize(up - glm::dot(up, f) * f);
  // Zooming or panning away ends where the data is far below a pixel in any view: the eye and
  // the target move back together to kFarthest scene radii from the centre. (Farther, float
  // depths on the GPU would not hold the frame: zooming out once ended the window.)
  const double reach = kFarthest * scale_of(bounds_);
  const glm::dvec3 from_centre = camera_.eye - bounds_.center();
  const double away = glm::length(from_centre);
  if (away > reach) {
    const glm::dvec3 look = camera_.target - camera_.eye;
    camera_.eye = bounds_.center() + from_centre * (reach / away);
    camera_.target = camera_.eye + look;
  }
  camera_.near_distance = std::min(camera_.near_distance, near_distance_for(camera_.eye, bounds_));
  // A near plane far closer than needed only costs depth precision; one too far cuts data.
  camera_.near_distance = std::max(camera_.near_distance, near_distance_for(camera_.eye, bounds_) * 1e-3);
}

void CameraController::rotate(glm::dvec2 pixels, glm::dvec2 viewport) {
  const double per_pixel = glm::pi<double>() / std::max(viewport.y, 1.0);
  const glm::dvec3 up = glm::normalize(camera_.up);
  // Dragging right turns the scene right: the eye moves left about the up axis...
  glm::dvec3 offset = turn(camera_.eye - camera_.target, -pixels.x * per_pixel, up);
  // ... and dragging down tilts it about the right axis of that turned view, up included.
  const glm::dvec3 right = glm::normalize(glm::cross(-offset, up));
  camera_.eye = camera_.target + turn(offset, -pixels.y * per_pixel, right);
  camera_.up = turn(up, -pixels.y * per_pixel, right);
  keep_valid();
}

void CameraController::pan(glm::dvec2 pixels, glm::dvec2 viewport) {
  const double distance = glm::length(camera_.target - camera_.eye);
  const double world_per_pixel = 2.0 * distance * std::tan(glm::radians(camera_.fovy_degrees) * 0.5) / std::max(viewport.y, 1.0);
  // Screen y grows downwards; the scene follows the cursor, so the camera moves the other way.
  const glm::dvec3 shift = (-pixels.x * right_of(camera_) + pixels.y * camera_.up) * world_per_pixel;
  camera_.eye += shift;
  camera_.target += shift;
  keep_valid();
}

void CameraController::zoom(double steps) {
  const glm::dvec3 offset = camera_.eye - camera_.target;
  const double min_distance = scale_of(bounds_) * 1e-3;
  double length = std::max(glm::length(offset) * std::pow(0.9, steps), min_distance);
  // Out no farther than keeps the eye within kFarthest radii of the data (keep_valid's bound),
  // the target staying where it is.
  const double target_away = glm::length(camera_.target - bounds_.center()), reach = kFarthest * scale_of(bounds_);
  if (target_away < reach) length = std::min(length, std::max(reach - target_away, min_distance));
  camera_.eye = camera_.target + glm::normalize(offset) * length;
  keep_valid();
}

void CameraController::reset(double aspect) {
  const glm::dvec3 direction = forward_of(camera_);
  camera_.target = bounds_.center();
  camera_.eye = camera_.target - direction * fit_distance(scale_of(bounds_), camera_.fovy_degrees, aspect);
  camera_.near_distance = near_distance_for(camera_.eye, bounds_);
  flying_ = false;
  keep_valid();
}

void CameraController::axis_view(AxisView view, double aspect) {
  static constexpr glm::dvec3 kX{1, 0, 0}, kY{0, 1, 0}, kZ{0, 0, 1};
  glm::dvec3 look{}, up{};
  switch (view) {  // ParaView: Z up when looking along X or Y, Y up when looking along Z
    case AxisView::PlusX: look = kX; up = kZ; break;
    case AxisView::MinusX: look = -kX; up = kZ; break;
    case AxisView::PlusY: look = kY; up = kZ; break;
    case AxisView::MinusY: look = -kY; up = kZ; break;
    case AxisView::PlusZ: look = kZ; up = kY; break;
    case AxisView::MinusZ: look = -kZ; up = kY; break;
  }
  camera_.up = up;
  camera_.target = bounds_.center();
  camera_.eye = camera_.target - look;
  reset(aspect);
}

void CameraController::set_flying(bool on) { flying_ = on; }

double CameraController::fly_speed() const { return 2.0 * scale_of(bounds_) / 5.0; }

void CameraController::fly_move(glm::dvec3 direction, double seconds) {
  const glm::dvec3 f = forward_of(camera_), r = right_of(camera_);
  const glm::dvec3 shift = (direction.x * r + direction.y * camera_.up + direction.z * f) * fly_speed() * seconds;
  camera_.eye += shift;
  camera_.target += shift;
  camera_.near_distance = near_distance_for(camera_.eye, bounds_);
  keep_valid();
}

void CameraController::fly_look(glm::dvec2 pixels, glm::dvec2 viewport) {
  const double per_pixel = glm::pi<double>() / std::max(viewport.y, 1.0);
  const glm::dvec3 up = glm::normalize(camera_.up), right = right_of(camera_);
  glm::dvec3 ahead = camera_.target - camera_.eye;
  ahead = turn(ahead, -pixels.x * per_pixel, up);
  ahead = turn(ahead, -pixels.y * per_pixel, right);
  camera_.up = turn(camera_.up, -pixels.y * per_pixel, right);
  camera_.target = camera_.eye + ahead;
  keep_valid();
}

}  // namespace prismoid::app
