#pragma once
// The CPU double-precision twin of shaders/surface/shadow_rays.glsl: the visibility of each
// light from a surface point, by the same rules (shaders/shared/surface.h states them):
//  - point and directional lights: one segment from the point moved off its surface along its
//    viewer-side geometric normal by offset(p) (PRISMOID_SHADOW_RAY_OFFSET times the scene's
//    scale), to the light's position less that distance, or to infinity;
//  - an emissive triangle: the ratio over the four fixed sample points of the shared table,
//    each weighted by max(cos at the point with the shading normal, 0) max(cos at the emitter,
//    0) / d^2 (0 below the geometric horizon, where the closed-form term is clipped away), each seen along the segment from the moved origin to the sample point moved off
//    the emitter towards its front; 1 when every weight is 0.
// Segments go through a TriangleBvh of all the scene's triangles in double, skipping the
// point's own triangle and the emitter's (which, past the offsets, no segment reaches in exact
// arithmetic either: the skips only keep double rounding out of the answer).
//
// Ambiguity: a float evaluation of the same segment differs from this one by a few ulps of the
// scene's scale (positions rounded to float relative to the origin, the float ray-triangle
// test). Each segment is traced again with both ends moved by ambiguity_distance() (2^-19 of
// the scale, 16 to 32 ulps) along +-x, +-y, +-z and with either end moved along the segment; a
// segment whose answer changes under any of these passes that close to an occluder's edge or
// ends there, and is reported ambiguous: the GPU may legitimately answer either way. The offset
// is 8 such distances, so a moved origin never sinks into the surface it leaves.
//
// Coordinates are world coordinates (double); the offsets' magnitudes are measured relative to
// the scene origin the GPU uses (the bounds centre, GpuSurfaceScene::origin).
#include <array>
#include <cstdint>

#include <glm/vec3.hpp>

#include "renderer/reference/triangle_bvh.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::reference {

struct ShadowVisibility {
  double value = 1.0;      // in [0, 1]
  bool ambiguous = false;  // some segment's answer changes under the nudges above
  uint32_t rays = 0;       // segments traced (nudges not counted)
};

// The barycentric weights (of corners 0, 1, 2) of emitter shadow sample k (the shared table).
glm::dvec3 emitter_shadow_sample(uint32_t k);

class ShadowRays {
 public:
  // Builds the hierarchy over all triangles, indexed by global triangle (mesh order).
  explicit ShadowRays(const SurfaceScene& scene);

  const glm::dvec3& origin() const { return origin_; }
  double scale() const { return scale_; }  // largest |vertex coordinate - origin| (SurfaceFrame subpixel.z)
  double offset(const glm::dvec3& p) const;
  double ambiguity_distance() const;

  // p: world position on global triangle `triangle`; geometric: its unit geometric normal on
  // the viewer's side (the side the light must be on).
  ShadowVisibility point_light(const glm::dvec3& p, const glm::dvec3& geometric, uint32_t triangle, const glm::dvec3& light) const;
  ShadowVisibility directional_light(const glm::dvec3& p, const glm::dvec3& geometric, uint32_t triangle,
                                     const glm::dvec3& to_light) const;
  // corners: the emitter's, in winding order; normal: its unit winding normal (the front).
  ShadowVisibility emitter(const glm::dvec3& p, const glm::dvec3& geometric, const glm::dvec3& shading_normal, uint32_t triangle,
                           const std::array<glm::dvec3, 3>& corners, const glm::dvec3& normal, uint32_t emitter_triangle) const;

  // Whether the segment origin + t direction, t in (0, t_max), is free of triangles other than
  // the skipped ones (t_max may be infinite); sets `ambiguous` when a nudge changes the answer.
  bool visible(const glm::dvec3& origin, const glm::dvec3& direction, double t_max, uint32_t skip_a, uint32_t skip_b,
               bool& ambiguous) const;

 private:
  glm::dvec3 origin_{0.0};
  double scale_ = 0.0;
  TriangleBvh bvh_;
};

}  // namespace prismoid::reference
