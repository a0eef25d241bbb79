#pragma once
// The CPU double-precision reference for exactly what the forward surface backend computes:
// direct light without shadows at the first surface along each pixel ray. It is what the GPU
// shading (shaders/surface/shading.glsl) is tested against; the path tracer
// (path_tracer.hpp) differs from it by design, by indirect light and shadows.
//
// At a surface point (conventions of scene/surface_scene.hpp and the path tracer: two-sided
// reflection, emission from the front side only, shading normal turned to the geometric
// normal's side and replaced by it when it faces away from the viewer) the radiance is
//   emission (front side)
//   + sum over point and directional lights of f(wo, wi) cos(theta_i) times the irradiance
//   + sum over emissive triangles (other than the point's own) of the integral over the
//     triangle's directions above both the geometric and the shading horizon of
//     Le f(wo, wi) cos(theta_i): the diffuse lobe in closed form (area_light.hpp), the GGX lobe
//     by the forward rule (AreaLightRule::Forward) or to 1e-9 (AreaLightRule::Exact)
//   + the sky as ambient light for the diffuse lobe: albedo times sky_cosine_mean (the
//     cosine-weighted mean of the sky's radiance over the shading normal's hemisphere, in
//     closed form), with nothing occluding the sky; the sky's reflection in the GGX lobe is
//     left out.
// Without `shadows` nothing casts shadows: every light is seen from every point above its
// horizons. With `shadows` each point, directional and emitter term is multiplied by the
// visibility the GPU's shadow rays compute (shaders/surface/shadow_rays.glsl), evaluated by its
// double twin (shadow_rays.hpp): one segment per point or directional light, the weighted
// ratio over four fixed points per emissive triangle; the sky stays unoccluded. Each sample
// then says whether any of its shadow segments is ambiguous (passes within a few float ulps of
// an occluder's edge, where a float evaluation may answer either way). A ray that hits
// nothing sees the sky.
//
// The scene is rendered as given: callers that want the "never black" rule apply
// with_default_lighting first.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/reference/path_tracer.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::reference {

enum class AreaLightRule { Forward, Exact };

struct DirectLightOptions {
  AreaLightRule area_rule = AreaLightRule::Forward;
  uint32_t subdivision = 4;         // the forward rule's n (PRISMOID_AREA_SPECULAR_SUBDIVISION)
  double exact_tolerance = 1e-9;    // Exact: relative to each emitter's GGX contribution
  unsigned threads = 0;             // 0: std::thread::hardware_concurrency()
  bool shadows = false;             // multiply each light by its shadow-ray visibility (above)
};

struct DirectLightSample {
  bool hit = false;
  uint32_t mesh = 0, triangle = 0;  // the surface hit (triangle index within its mesh)
  uint32_t global_triangle = 0;     // its index among all meshes' triangles, in mesh order
  double t = 0.0;                   // ray parameter of the hit
  glm::dvec3 radiance{0.0};
  // For float tolerances. rounding_scale: the sum over the terms added up of |term| (largest
  // channel) times the term's condition: Lambert's edge sum counts its absolute sum; a GGX
  // term counts max(1, 2 / (1 + (n.h)^2 (alpha^2 - 1))), by which D's denominator amplifies the
  // rounding of n.h. A float evaluation that rounds each operation's result by at most u
  // relatively, with k operations per term, is then off by about k u rounding_scale, plus
  // terms u rounding_scale for the summation.
  double rounding_scale = 0.0;
  uint32_t terms = 0;
  // With shadows: whether any shadow segment of this point is ambiguous, and how many were traced.
  bool shadow_ambiguous = false;
  uint32_t shadow_rays = 0;
};

// One sample per ray (SurfaceRay: origin, direction, t_min).
std::vector<DirectLightSample> direct_light(const SurfaceScene& scene, std::span<const SurfaceRay> rays,
                                            const DirectLightOptions& options = {});

// Direct light at given surface points rather than at rays' first hits: what texel-space
// backends shade (an Htex texel's point may be a vertex, or a ghost point in a face's plane
// beyond a boundary, so it is given as mesh, triangle and barycentric weights, any of which may
// be negative). The viewer is at `eye`; nothing is traced.
struct ShadingPointQuery {
  uint32_t mesh = 0, triangle = 0;  // triangle index within its mesh
  glm::dvec3 bary{1.0 / 3.0};       // weights of the triangle's corners
  glm::dvec3 eye{0.0};
};
std::vector<DirectLightSample> direct_light_at(const SurfaceScene& scene, std::span<const ShadingPointQuery> points,
                                               const DirectLightOptions& options = {});

struct DirectLightImage {
  uint32_t width = 0, height = 0;
  std::vector<DirectLightSample> pixels;  // row-major, row 0 at the top
  std::vector<float> rgb() const;         // 3 floats per pixel, as PFM and image_error take them
};
// Pixel (x, y) is sampled through the image point (x + 0.5 + offset_x, y + 0.5 + offset_y)
// (ray_direction in tet_ray.hpp), from the eye, beyond the near plane.
DirectLightImage direct_light_image(const SurfaceScene& scene, const Camera& camera, uint32_t width, uint32_t height,
                                    double offset_x = 0.0, double offset_y = 0.0, const DirectLightOptions& options = {});
// The image averaged over k x k sample points per pixel, at offsets ((i + 0.5) / k - 0.5) in x and y.
std::vector<glm::dvec3> supersampled_direct_light(const SurfaceScene& scene, const Camera& camera, uint32_t width,
                                                  uint32_t height, uint32_t k, const DirectLightOptions& options = {});

// The cosine-weighted mean of the sky's radiance over the hemisphere around the unit normal n,
// (1/pi) integral of L(w) max(0, n.w) dw. For the linear gradient of Sky::radiance it is
// (top + bottom) / 2 + (top - bottom) dot(up, n) / 3, since the hemisphere's integral of
// (w.u)(w.n) is 2 pi / 3 (u.n).
glm::dvec3 sky_cosine_mean(const Sky& sky, const glm::dvec3& n);

}  // namespace prismoid::reference
