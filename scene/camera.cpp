#include "scene/camera.hpp"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {

glm::dmat4 view_matrix(const Camera& camera, const glm::dvec3& origin) {
  const glm::dvec3 eye = camera.eye - origin;
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  glm::dmat4 m(1.0);
  m[0][0] = right.x; m[1][0] = right.y; m[2][0] = right.z;
  m[0][1] = up.x;    m[1][1] = up.y;    m[2][1] = up.z;
  m[0][2] = -forward.x; m[1][2] = -forward.y; m[2][2] = -forward.z;
  m[3][0] = -glm::dot(right, eye);
  m[3][1] = -glm::dot(up, eye);
  m[3][2] = glm::dot(forward, eye);
  return m;
}

glm::dmat4 projection_matrix(const Camera& camera, double aspect) {
  const double f = 1.0 / std::tan(glm::radians(camera.fovy_degrees) * 0.5);
  glm::dmat4 p(0.0);
  p[0][0] = f / aspect;
  p[1][1] = -f;  // Vulkan's framebuffer y points down
  // Reversed z with an infinite far plane: ndc depth = near / d and clip.w = d, the distance
  // along the viewing axis. The volume passes carry their depths in attributes instead.
  p[2][2] = 0.0;
  p[2][3] = -1.0;
  p[3][2] = camera.near_distance;
  return p;
}

Camera fit_camera(const Bounds& bounds, double fovy_degrees) {
  Camera c;
  c.fovy_degrees = fovy_degrees;
  // Any positive size frames (data of 1e-20 are as visible as data of 1e20); a single point,
  // which has none, gets a unit sphere around it.
  const double r = bounds.radius();
  const double radius = r > 0.0 && std::isfinite(r) ? r : 1.0;
  const double distance = radius / std::sin(glm::radians(fovy_degrees) * 0.5) * 1.05;
  c.target = bounds.center();
  c.eye = c.target + glm::dvec3(0.0, 0.0, distance);
  c.near_distance = std::max(distance - radius, distance * 1e-3) * 0.5;
  return c;
}

void validate(const Camera& camera) {
  auto finite = [](const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (!finite(camera.eye) || !finite(camera.target) || !finite(camera.up)) throw InputError("camera", "has a non-finite coordinate");
  const glm::dvec3 forward = camera.target - camera.eye;
  const double len = glm::length(forward);
  if (len == 0.0) throw InputError("camera", "eye and target are the same point");
  const double up_len = glm::length(camera.up);
  if (up_len == 0.0) throw InputError("camera", "up vector is zero: it needs a direction");
  if (glm::length(glm::cross(forward / len, camera.up / up_len)) < 1e-9)
    throw InputError("camera", "up vector is parallel to the viewing direction");
  if (!(camera.fovy_degrees > 0.0 && camera.fovy_degrees < 180.0))
    throw InputError("camera", "--fovy must lie strictly between 0 and 180 degrees");
  if (!(camera.near_distance > 0.0) || !std::isfinite(camera.near_distance))
    throw InputError("camera", "--near must be a positive distance");
}

}  // namespace prismoid
