#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>

#include "scene/camera.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {
namespace {

TEST(Camera, ViewMatrixPutsTheTargetOnTheNegativeZAxis) {
  Camera c;
  c.eye = {3, 4, 5};
  c.target = {1, -1, 2};
  const glm::dvec4 t = view_matrix(c, glm::dvec3(0.0)) * glm::dvec4(c.target, 1.0);
  EXPECT_NEAR(t.x, 0.0, 1e-12);
  EXPECT_NEAR(t.y, 0.0, 1e-12);
  EXPECT_NEAR(t.z, -glm::length(c.target - c.eye), 1e-12);
}

TEST(Camera, LocalOriginGivesTheSameCameraSpaceFarFromTheOrigin) {
  // Data at 1e7 expressed relative to its own centre keeps its precision in float.
  const glm::dvec3 origin(1e7, -3e6, 5e6);
  Camera c;
  c.eye = origin + glm::dvec3(0, 0, 4);
  c.target = origin;
  const glm::dvec3 p = origin + glm::dvec3(0.001, 0.002, 0.003);
  const glm::dvec4 local = view_matrix(c, origin) * glm::dvec4(p - origin, 1.0);
  // p itself carries the rounding of a double at 1e7: 1e7 * 2^-52 per coordinate.
  const double tol = 4.0 * 1e7 * std::ldexp(1.0, -52);
  EXPECT_NEAR(local.x, 0.001, tol);
  EXPECT_NEAR(local.y, 0.002, tol);
  EXPECT_NEAR(local.z, 0.003 - 4.0, tol);
  // The same in float, as the GPU receives it: no worse than float's own rounding of 4.
  const glm::vec4 local_f = glm::mat4(view_matrix(c, origin)) * glm::vec4(glm::vec3(p - origin), 1.0f);
  EXPECT_NEAR(local_f.x, 0.001, 1e-6);
  EXPECT_NEAR(local_f.z, 0.003 - 4.0, 1e-6);
}

TEST(Camera, ProjectionDividesByDepth) {
  Camera c;
  c.fovy_degrees = 90.0;
  const glm::dvec4 clip = projection_matrix(c, 2.0) * glm::dvec4(1.0, 1.0, -2.0, 1.0);
  EXPECT_NEAR(clip.w, 2.0, 1e-12);
  EXPECT_NEAR(clip.x / clip.w, 0.25, 1e-12);  // x / (d * tan(45deg) * aspect)
  EXPECT_NEAR(clip.y / clip.w, -0.5, 1e-12);  // Vulkan y points down
}

TEST(Camera, FitCameraSeesTheWholeBounds) {
  Bounds b{{-1, -2, -3}, {4, 5, 6}};
  const Camera c = fit_camera(b, 40.0);
  EXPECT_GT(glm::length(c.eye - b.center()), b.radius());
  EXPECT_GT(c.near_distance, 0.0);
  EXPECT_LT(c.near_distance, glm::length(c.eye - b.center()) - b.radius());
}

TEST(Camera, BadCamerasAreInputErrors) {
  Camera c;
  c.target = c.eye;
  EXPECT_THROW(validate(c), InputError);
  c = Camera{};
  c.up = c.target - c.eye;
  EXPECT_THROW(validate(c), InputError);
  c = Camera{};
  c.fovy_degrees = 180.0;
  EXPECT_THROW(validate(c), InputError);
  c = Camera{};
  c.near_distance = 0.0;
  EXPECT_THROW(validate(c), InputError);
}

}  // namespace
}  // namespace prismoid
