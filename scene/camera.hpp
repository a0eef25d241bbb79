#pragma once
// A pinhole camera in world coordinates, kept in double precision. The renderer turns it
// into float matrices relative to a mesh's local origin, so far-from-origin data keeps its
// precision.
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace prismoid {

struct Bounds;

struct Camera {
  glm::dvec3 eye{0.0, 0.0, 5.0};
  glm::dvec3 target{0.0};
  glm::dvec3 up{0.0, 1.0, 0.0};
  double fovy_degrees = 40.0;
  double near_distance = 0.01;
  bool operator==(const Camera&) const = default;  // the same view, exactly
};

// World -> camera transform for a scene whose coordinates are given relative to `origin`.
glm::dmat4 view_matrix(const Camera& camera, const glm::dvec3& origin);
// Camera -> Vulkan clip space (y down, depth 0..1, infinite far plane).
glm::dmat4 projection_matrix(const Camera& camera, double aspect);
// A camera that looks at the bounds from the +z side, framing them.
Camera fit_camera(const Bounds& bounds, double fovy_degrees = 40.0);

// Throws InputError("camera", ...) for a camera that cannot make an image (eye == target,
// up parallel to the view direction, fovy outside (0, 180), near <= 0, non-finite values).
void validate(const Camera& camera);

}  // namespace prismoid
