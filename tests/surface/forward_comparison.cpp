#include "surface/forward_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <sstream>

#include <glm/geometric.hpp>

#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/vk/device.hpp"
#include "shaders/shared/surface.h"

// The reference evaluates the GGX area-light rule the shaders use.
static_assert(prismoid::reference::DirectLightOptions{}.subdivision == PRISMOID_AREA_SPECULAR_SUBDIVISION);

namespace prismoid::test {

namespace {

double max_abs(const glm::dvec3& v) { return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z))); }

// Whether two hits are on the same triangle or on triangles of one mesh sharing a corner, so
// that the radiance between them is what the rasterizer may interpolate (its change is allowed).
bool touching(const SurfaceScene& scene, const reference::DirectLightSample& a, const reference::DirectLightSample& b) {
  if (a.hit != b.hit) return false;
  if (!a.hit) return true;
  if (a.mesh != b.mesh) return false;
  if (a.triangle == b.triangle) return true;
  const auto& ta = scene.meshes[a.mesh].triangles[a.triangle];
  const auto& tb = scene.meshes[b.mesh].triangles[b.triangle];
  for (uint32_t i : ta)
    for (uint32_t j : tb)
      if (i == j) return true;
  return false;
}

}  // namespace

std::vector<ForwardTolerance> forward_tolerances(uint32_t subpixel_bits, const SurfaceScene& scene, const Camera& camera, uint32_t width,
                                                 uint32_t height, glm::dvec2 subpixel, bool shadows) {
  const double radius = 2.0 * std::ldexp(1.0, -int(subpixel_bits));
  constexpr int kProbes = 8;
  const size_t pixels = size_t(width) * height;
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  std::vector<reference::SurfaceRay> rays;
  rays.reserve(pixels * (kProbes + 1));
  for (int k = 0; k <= kProbes; ++k) {
    const double angle = k == 0 ? 0.0 : (k - 1) * (2.0 * 3.14159265358979 / kProbes);
    const double dx = k == 0 ? 0.0 : radius * std::cos(angle), dy = k == 0 ? 0.0 : radius * std::sin(angle);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const glm::dvec3 d = reference::ray_direction(camera, width, height, x + 0.5 + subpixel.x + dx, y + 0.5 + subpixel.y + dy);
        rays.push_back({camera.eye, d, camera.near_distance / glm::dot(d, forward)});
      }
  }
  reference::DirectLightOptions options;
  options.shadows = shadows;
  const auto samples = reference::direct_light(scene, rays, options);
  std::vector<ForwardTolerance> out(pixels);
  for (size_t i = 0; i < pixels; ++i) {
    ForwardTolerance& t = out[i];
    t.centre = samples[i];
    for (int k = 1; k <= kProbes; ++k) {
      const auto& probe = samples[k * pixels + i];
      if (!touching(scene, t.centre, probe)) t.silhouette = true;
      t.variation = std::max(t.variation, max_abs(probe.radiance - t.centre.radiance));
    }
    t.ambiguous = t.centre.shadow_ambiguous;
    t.rounding = 0x1p-24 * (kUlpBudget + t.centre.terms) * t.centre.rounding_scale;
    // The shadowed pass shades the plane of the triangle the rasterizer kept, met by the centre
    // ray: where that is a neighbour seen by a probe r away, its value at the centre differs from
    // the probe's by about that neighbour's change over r, bounded by the variation once more.
    t.tolerance = (shadows ? 2.0 : 1.0) * t.variation + t.rounding;
  }
  return out;
}

namespace {

// r.gpu filled: compares it pixel by pixel with the twin (shadows or not).
void compare_with_reference(const vk::Device& device, ForwardComparison& r, const SurfaceScene& scene, const Camera& camera,
                            uint32_t width, uint32_t height, glm::dvec2 subpixel, bool shadows);

}  // namespace

ForwardComparison compare_forward(const vk::Device& device, surface::ForwardPass& pass, const SurfaceScene& scene,
                                  const Camera& camera, uint32_t width, uint32_t height, glm::dvec2 subpixel) {
  ForwardComparison r;
  const surface::GpuSurfaceScene gpu_scene = surface::upload(device, scene);
  surface::ForwardSettings settings;
  settings.subpixel = subpixel;
  r.gpu = surface::render_forward(device, pass, gpu_scene, camera, {width, height}, settings);
  compare_with_reference(device, r, scene, camera, width, height, subpixel, false);
  return r;
}

ForwardComparison compare_forward_shadowed(const vk::Device& device, surface::ShadowedForwardPass& pass, const SurfaceScene& scene,
                                           const Camera& camera, uint32_t width, uint32_t height, glm::dvec2 subpixel) {
  ForwardComparison r;
  const surface::GpuSurfaceScene gpu_scene = surface::upload(device, scene);
  const rt::SceneAccel accel(device, scene);
  surface::ForwardSettings settings;
  settings.subpixel = subpixel;
  r.gpu = surface::render_forward_shadowed(device, pass, gpu_scene, accel, camera, {width, height}, settings);
  compare_with_reference(device, r, scene, camera, width, height, subpixel, true);
  return r;
}

namespace {

void compare_with_reference(const vk::Device& device, ForwardComparison& r, const SurfaceScene& scene, const Camera& camera,
                            uint32_t width, uint32_t height, glm::dvec2 subpixel, bool shadows) {
  const std::vector<ForwardTolerance> allowed =
      forward_tolerances(device.capabilities().subpixel_precision_bits, scene, camera, width, height, subpixel, shadows);
  std::vector<reference::DirectLightSample> unshadowed;
  if (shadows) {
    std::vector<reference::SurfaceRay> rays;
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    for (uint32_t y = 0; y < height; ++y)
      for (uint32_t x = 0; x < width; ++x) {
        const glm::dvec3 d = reference::ray_direction(camera, width, height, x + 0.5 + subpixel.x, y + 0.5 + subpixel.y);
        rays.push_back({camera.eye, d, camera.near_distance / glm::dot(d, forward)});
      }
    unshadowed = reference::direct_light(scene, rays);
  }
  const size_t pixels = size_t(width) * height;
  r.pixels = pixels;
  for (size_t i = 0; i < pixels; ++i) {
    const float* g = &r.gpu.rgba[i * 4];
    for (int c = 0; c < 4; ++c) r.finite = r.finite && std::isfinite(g[c]);
    const ForwardTolerance& t = allowed[i];
    const auto& centre = t.centre;
    if (centre.hit) ++r.covered;
    if (t.silhouette) {
      ++r.excluded;
      continue;
    }
    if (t.ambiguous) {
      ++r.ambiguous;
      continue;
    }
    ++r.compared;
    const double tolerance = t.tolerance;
    if (shadows && max_abs(unshadowed[i].radiance - centre.radiance) > tolerance) ++r.shadowed;
    r.max_rounding_tolerance = std::max(r.max_rounding_tolerance, t.rounding);
    r.peak_radiance = std::max(r.peak_radiance, max_abs(centre.radiance));
    bool ok = g[3] == (centre.hit ? 1.0f : 0.0f);
    for (int c = 0; c < 3; ++c) {
      const double error = std::abs(double(g[c]) - centre.radiance[c]);
      r.max_error = std::max(r.max_error, error);
      if (tolerance > 0.0) r.max_ratio = std::max(r.max_ratio, error / tolerance);
      ok = ok && error <= tolerance;
    }
    if (!ok) {
      if (r.failures == 0) {
        std::ostringstream s;
        s << "pixel (" << i % width << ", " << i / width << "): GPU (" << g[0] << ", " << g[1] << ", " << g[2] << ", " << g[3]
          << "), reference (" << centre.radiance.x << ", " << centre.radiance.y << ", " << centre.radiance.z << ", hit "
          << centre.hit << "), tolerance " << tolerance << " (probes " << t.variation << ", rounding " << t.rounding << ")";
        r.first_failure = s.str();
      }
      ++r.failures;
    }
  }
}

}  // namespace

}  // namespace prismoid::test
