#pragma once
// The first use of the ray-tracing foundation, and the one checked against the CPU reference:
// primary rays from a camera (what each pixel sees first) and shadow rays (whether segments are
// free), traced through one ray-tracing pipeline (two ray-generation shaders, a closest-hit
// shader, two miss shaders; shaders/rt/). Rays are traced, never queried: no ray queries.
//
// Camera rays follow the CPU reference's convention (reference::ray_direction in
// renderer/reference/tet_ray.hpp, as the path tracer and first_hits use it): one ray through
// each pixel's centre, row 0 at the top, starting at the near plane (t = near /
// dot(direction, forward)). The camera frame is computed in double and handed over in float,
// relative to the scene's origin (SceneAccel).
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/vk/handle.hpp"
#include "scene/camera.hpp"

namespace prismoid::rt {

struct RayHit {
  bool hit = false;
  float t = -1.0f;          // distance along the unit ray direction from the eye (float, as traced)
  float b1 = 0.0f, b2 = 0.0f;  // barycentric weights of the triangle's 2nd and 3rd vertex
  uint32_t mesh = 0, triangle = 0;
};

// A segment from + s (to - from) for s in [s_min, s_max] (world coordinates, double).
struct ShadowSegment {
  glm::dvec3 from{0.0};
  glm::dvec3 to{0.0};
  double s_min = 0.0;
  double s_max = 1.0;
};

class RayCaster {
 public:
  // Keeps a reference to `accel`, which must outlive the caster. Throws vk::NoSuitableDevice
  // when the device has no ray tracing enabled.
  RayCaster(const vk::Device& device, const SceneAccel& accel);

  // One ray per pixel, row-major, row 0 at the top. Throws InputError for an invalid camera or
  // a zero image size.
  std::vector<RayHit> primary_hits(const Camera& camera, uint32_t width, uint32_t height) const;

  // Per segment: 1 when no triangle lies on it, 0 when one does (opaque geometry, the first hit
  // found ends the search, no closest-hit shader runs). Throws InputError for a non-finite
  // segment or an empty or negative parameter range.
  std::vector<uint8_t> visibility(std::span<const ShadowSegment> segments) const;

  // Whether a point light at `light` reaches each point: segments point -> light with
  // s in [spawn / length, 1 - spawn / length], i.e. `spawn` (world length) is skipped at both
  // ends so neither the surface the point lies on nor the light's own geometry counts.
  std::vector<uint8_t> point_light_visibility(std::span<const glm::dvec3> points, const glm::dvec3& light, double spawn) const;

 private:
  const vk::Device& device_;
  const SceneAccel& accel_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  RayTracingPipeline pipeline_;
};

}  // namespace prismoid::rt
