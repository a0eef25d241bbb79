#include "renderer/reference/shadow_rays.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>

#include "shaders/shared/surface.h"

namespace prismoid::reference {

namespace {

std::vector<TriangleBvh::Triangle> flatten(const SurfaceScene& scene) {
  std::vector<TriangleBvh::Triangle> out;
  for (const SceneMesh& mesh : scene.meshes)
    for (const auto& t : mesh.triangles) out.push_back({mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]});
  return out;
}

double max_abs(const glm::dvec3& v) { return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z))); }

// The ambiguity distance as a fraction of the scale: 2^-19 (the offset is 2^-16).
constexpr double kAmbiguity = 0x1p-19;
static_assert(PRISMOID_SHADOW_RAY_OFFSET == 0x1p-16);
static_assert(PRISMOID_EMITTER_SHADOW_SAMPLES == 4u);

}  // namespace

glm::dvec3 emitter_shadow_sample(uint32_t k) {
  static const glm::dvec3 samples[PRISMOID_EMITTER_SHADOW_SAMPLES] = {
      glm::dvec3(PRISMOID_EMITTER_SHADOW_SAMPLE_0), glm::dvec3(PRISMOID_EMITTER_SHADOW_SAMPLE_1),
      glm::dvec3(PRISMOID_EMITTER_SHADOW_SAMPLE_2), glm::dvec3(PRISMOID_EMITTER_SHADOW_SAMPLE_3)};
  return samples[k];
}

ShadowRays::ShadowRays(const SurfaceScene& scene) : bvh_(flatten(scene)) {
  const Bounds b = bounds_of(scene);
  origin_ = b.center();
  scale_ = max_abs(b.max - origin_);
}

double ShadowRays::offset(const glm::dvec3& p) const {
  const double m = max_abs(p - origin_);
  return PRISMOID_SHADOW_RAY_OFFSET * (scale_ > 0.0 ? std::max(m, scale_) : std::max(m, 1.0));
}

double ShadowRays::ambiguity_distance() const { return kAmbiguity * (scale_ > 0.0 ? scale_ : 1.0); }

bool ShadowRays::visible(const glm::dvec3& origin, const glm::dvec3& direction, double t_max, uint32_t skip_a, uint32_t skip_b,
                         bool& ambiguous) const {
  if (!(t_max > 0.0)) return true;
  const bool free = !bvh_.occluded(origin, direction, 0.0, t_max, skip_a, skip_b);
  const double eps = ambiguity_distance();
  const double len = glm::length(direction);
  const glm::dvec3 unit = direction / len;
  auto differs = [&](const glm::dvec3& o, double t) { return !bvh_.occluded(o, direction, 0.0, t, skip_a, skip_b) != free; };
  for (int axis = 0; axis < 3 && !ambiguous; ++axis)
    for (double sign : {-1.0, 1.0}) {
      glm::dvec3 shift(0.0);
      shift[axis] = sign * eps;
      if (differs(origin + shift, t_max)) {
        ambiguous = true;
        break;
      }
    }
  if (!ambiguous && std::isfinite(t_max)) {
    const double dt = eps / len;  // either end moved along the segment by eps
    ambiguous = differs(origin, t_max + dt) || differs(origin, std::max(t_max - dt, 0.0)) ||
                differs(origin + unit * eps, std::max(t_max - dt, 0.0)) || differs(origin - unit * eps, t_max + dt);
  } else if (!ambiguous) {
    ambiguous = differs(origin + unit * eps, t_max) || differs(origin - unit * eps, t_max);
  }
  return free;
}

ShadowVisibility ShadowRays::point_light(const glm::dvec3& p, const glm::dvec3& geometric, uint32_t triangle,
                                         const glm::dvec3& light) const {
  ShadowVisibility v;
  const double off = offset(p);
  const glm::dvec3 origin = p + geometric * off;
  const glm::dvec3 to = light - origin;
  const double d = glm::length(to);
  if (!(d > off)) return v;
  v.rays = 1;
  v.value = visible(origin, to / d, d - off, triangle, kNoTriangle, v.ambiguous) ? 1.0 : 0.0;
  return v;
}

ShadowVisibility ShadowRays::directional_light(const glm::dvec3& p, const glm::dvec3& geometric, uint32_t triangle,
                                               const glm::dvec3& to_light) const {
  ShadowVisibility v;
  v.rays = 1;
  v.value = visible(p + geometric * offset(p), to_light, std::numeric_limits<double>::infinity(), triangle, kNoTriangle, v.ambiguous)
                ? 1.0
                : 0.0;
  return v;
}

ShadowVisibility ShadowRays::emitter(const glm::dvec3& p, const glm::dvec3& geometric, const glm::dvec3& shading_normal,
                                     uint32_t triangle, const std::array<glm::dvec3, 3>& corners, const glm::dvec3& normal,
                                     uint32_t emitter_triangle) const {
  ShadowVisibility v;
  const glm::dvec3 origin = p + geometric * offset(p);
  double seen = 0.0, total = 0.0;
  for (uint32_t k = 0; k < PRISMOID_EMITTER_SHADOW_SAMPLES; ++k) {
    const glm::dvec3 b = emitter_shadow_sample(k);
    const glm::dvec3 q = b.x * corners[0] + b.y * corners[1] + b.z * corners[2];
    const glm::dvec3 to = q - p;
    const double d2 = glm::dot(to, to);
    if (!(d2 > 0.0)) continue;
    const glm::dvec3 w = to / std::sqrt(d2);
    const double weight =
        glm::dot(w, geometric) > 0.0 ? std::max(glm::dot(w, shading_normal), 0.0) * std::max(-glm::dot(w, normal), 0.0) / d2 : 0.0;
    if (!(weight > 0.0)) continue;
    total += weight;
    const glm::dvec3 segment = q + normal * offset(q) - origin;
    const double length = glm::length(segment);
    if (!(length > 0.0)) {
      seen += weight;
      continue;
    }
    ++v.rays;
    if (visible(origin, segment / length, length, triangle, emitter_triangle, v.ambiguous)) seen += weight;
  }
  v.value = total > 0.0 ? seen / total : 1.0;
  return v;
}

}  // namespace prismoid::reference
