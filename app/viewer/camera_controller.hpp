#pragma once
// The viewer's camera, ParaView's way: trackball rotation about the target, pan, zoom, reset to
// fit, axis-aligned views, and a fly mode that moves the eye itself (into the volume). Pure
// logic over a Camera and the scene's bounds: no window, unit-tested on its own. Mouse motion
// arrives in pixels with the viewport's size, so speeds do not depend on the window.
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/bounds.hpp"
#include "scene/camera.hpp"

namespace prismoid::app {

// ParaView's "Set view direction to ..." buttons: the direction the camera looks along.
enum class AxisView { PlusX, MinusX, PlusY, MinusY, PlusZ, MinusZ };
const char* axis_view_name(AxisView view);  // "+X", "-X", ...

class CameraController {
 public:
  // The farthest the eye goes from the bounds' centre, in bounds radii: there the data covers
  // about a millionth of the view's height, under a pixel on any screen.
  static constexpr double kFarthest = 1e6;

  explicit CameraController(const Bounds& bounds);
  CameraController(const Bounds& bounds, const Camera& camera);

  const Camera& camera() const { return camera_; }
  void set_camera(const Camera& camera);  // keeps its near plane only where it is valid
  const Bounds& bounds() const { return bounds_; }

  // Trackball: horizontal motion turns about the camera's up, vertical about its right; the
  // eye keeps its distance to the target. A drag over the viewport's height turns 180 degrees.
  void rotate(glm::dvec2 pixels, glm::dvec2 viewport);
  // Moves eye and target together so the point under the cursor (at the target's depth)
  // follows the cursor.
  void pan(glm::dvec2 pixels, glm::dvec2 viewport);
  // Moves the eye towards (steps > 0) or away from the target by a factor 0.9 per step.
  void zoom(double steps);
  // Looks at the bounds' centre from the current direction, the bounding sphere inside the
  // narrower of the two fields of view.
  void reset(double aspect);
  void axis_view(AxisView view, double aspect);

  // Fly mode: the eye moves and looks around itself; the target stays one "look distance"
  // ahead of the eye.
  bool flying() const { return flying_; }
  void set_flying(bool on);
  // `direction` in camera axes: x right, y up, z forward; moves `seconds` at fly_speed().
  void fly_move(glm::dvec3 direction, double seconds);
  // Turns the view direction about the eye (mouse look), 180 degrees per viewport height.
  void fly_look(glm::dvec2 pixels, glm::dvec2 viewport);
  double fly_speed() const;  // world units per second: a fifth of the bounds' diagonal

 private:
  void keep_valid();  // re-orthogonalizes up and places the near plane

  Bounds bounds_;
  Camera camera_;
  bool flying_ = false;
};

// A near-plane distance that never cuts the data in front of the eye: half the distance from
// the eye to the bounds, and a small fraction of their size once the eye is inside them (the
// renderer clips cells at the near plane, so a camera inside the volume still sees it).
double near_distance_for(const glm::dvec3& eye, const Bounds& bounds);

}  // namespace prismoid::app
