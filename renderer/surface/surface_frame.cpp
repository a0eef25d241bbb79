#include "renderer/surface/surface_frame.hpp"

#include <cmath>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace prismoid::surface {

gpu::SurfaceFrame surface_frame(const GpuSurfaceScene& scene, const Camera& camera, VkExtent2D e, const glm::dvec2& subpixel) {
  gpu::SurfaceFrame f{};
  const double aspect = double(e.width) / double(e.height);
  f.view = glm::mat4(view_matrix(camera, scene.origin));
  glm::dmat4 projection = projection_matrix(camera, aspect);
  // Sample the image point (x + 0.5 + s.x, y + 0.5 + s.y) at pixel (x, y)'s centre: shift the
  // image by -s pixels, i.e. ndc by -2 s / size; clip.w = -z, so the shift enters column 2.
  projection[2][0] += 2.0 * subpixel.x / double(e.width);
  projection[2][1] += 2.0 * subpixel.y / double(e.height);
  f.projection = glm::mat4(projection);
  f.viewport = glm::vec4(float(e.width), float(e.height), 1.0f / float(e.width), 1.0f / float(e.height));
  f.eye = glm::vec4(glm::vec3(camera.eye - scene.origin), 1.0f);
  f.counts = glm::uvec4(scene.point_light_count, scene.directional_light_count, scene.emitter_count, scene.sky.black() ? 0u : 1u);
  f.sky_top = glm::vec4(glm::vec3(scene.sky.top), 0.0f);
  f.sky_bottom = glm::vec4(glm::vec3(scene.sky.bottom), 0.0f);
  f.sky_up = glm::vec4(glm::vec3(glm::normalize(scene.sky.up)), 0.0f);
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const double tan_half = std::tan(glm::radians(camera.fovy_degrees) * 0.5);
  f.camera_right = glm::vec4(glm::vec3(right), float(tan_half * aspect));
  f.camera_up = glm::vec4(glm::vec3(up), float(tan_half));
  f.camera_forward = glm::vec4(glm::vec3(forward), 0.0f);
  f.subpixel = glm::vec4(float(subpixel.x), float(subpixel.y), float(scene.scale), 0.0f);  // z: the shadow rays' scale
  return f;
}


}  // namespace prismoid::surface
