#pragma once
// The forward backend's image against the CPU direct-light reference, pixel by pixel, with a
// tolerance derived per pixel:
//  - snapping: the rasterizer moves vertices to its sub-pixel grid (2^-bits pixel) and
//    interpolates in float, so the point a pixel shades may be any within r = 2 * 2^-bits pixel
//    of the pixel centre's ray hit. The reference is evaluated along 8 rays at distance r around
//    the centre; the largest change of the radiance there is allowed. A pixel where one of those
//    rays sees the sky or a triangle not touching the centre's (a silhouette: which surface the
//    rasterizer keeps there is not fixed) is left out.
//  - rounding: the GPU evaluates in float. Each term (one light, one area-light node) takes a
//    few tens of float operations, each rounded within 2.5 ulp (Vulkan: division 2.5 ulp,
//    inversesqrt 2 ulp; our atan2 within 4 ulp, tests/surface/test_area_light.cpp); kUlpBudget
//    ulps per term, times the reference's rounding_scale (terms weighted by their condition),
//    plus one ulp of the summed magnitude per term added (recursive summation).
#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::test {

inline constexpr double kUlpBudget = 128.0;

struct ForwardComparison {
  size_t pixels = 0;
  size_t covered = 0;     // the reference's centre ray hits a surface
  size_t compared = 0;
  size_t excluded = 0;    // silhouette band
  size_t failures = 0;
  std::string first_failure;
  double max_error = 0.0;       // over compared pixels and channels
  double max_ratio = 0.0;       // max error / tolerance
  double max_rounding_tolerance = 0.0;  // the rounding part of the tolerance
  double peak_radiance = 0.0;           // the reference's largest value
  size_t ambiguous = 0;   // with shadows: the centre's shadow rays pass within the twin's ambiguity distance of an edge (left out)
  size_t shadowed = 0;    // with shadows: compared pixels the shadows change (beyond the tolerance)
  bool finite = true;           // every GPU value finite (all pixels, excluded ones too)
  surface::ForwardImage gpu;
};

// Per pixel, what the comparison above allows: the reference's centre sample, whether the pixel
// is compared (not on a silhouette, no ambiguous shadow ray) and its tolerance (per channel).
struct ForwardTolerance {
  reference::DirectLightSample centre;
  bool silhouette = false, ambiguous = false;
  double tolerance = 0.0, variation = 0.0, rounding = 0.0;
  bool compared() const { return !silhouette && !ambiguous; }
};
std::vector<ForwardTolerance> forward_tolerances(uint32_t subpixel_bits, const SurfaceScene& scene, const Camera& camera, uint32_t width,
                                                 uint32_t height, glm::dvec2 subpixel, bool shadows);

ForwardComparison compare_forward(const vk::Device& device, surface::ForwardPass& pass, const SurfaceScene& scene,
                                  const Camera& camera, uint32_t width, uint32_t height, glm::dvec2 subpixel = glm::dvec2(0.0));

// The shadowed forward pass against the CPU twin with shadows (DirectLightOptions::shadows), by
// the same rule; a pixel whose centre sample has an ambiguous shadow ray is counted, not compared.
ForwardComparison compare_forward_shadowed(const vk::Device& device, surface::ShadowedForwardPass& pass, const SurfaceScene& scene,
                                           const Camera& camera, uint32_t width, uint32_t height,
                                           glm::dvec2 subpixel = glm::dvec2(0.0));

}  // namespace prismoid::test
