#include "renderer/reference/direct_light.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <optional>
#include <thread>

#include <glm/geometric.hpp>

#include "renderer/reference/area_light.hpp"
#include "renderer/reference/shadow_rays.hpp"
#include "renderer/reference/surface_bsdf.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::reference {

namespace {

constexpr double kPi = std::numbers::pi;

double max_of(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
double max_abs(const glm::dvec3& v) { return max_of(glm::abs(v)); }
bool positive(const glm::dvec3& v) { return v.x > 0.0 || v.y > 0.0 || v.z > 0.0; }

// Any orthonormal frame around a unit normal: the BSDF depends only on angles to the normal
// and between the directions.
struct Basis {
  glm::dvec3 t, b, n;
  explicit Basis(const glm::dvec3& normal) : n(normal) {
    const glm::dvec3 axis = std::abs(n.x) < 0.9 ? glm::dvec3(1.0, 0.0, 0.0) : glm::dvec3(0.0, 1.0, 0.0);
    t = glm::normalize(glm::cross(axis, n));
    b = glm::cross(n, t);
  }
  glm::dvec3 local(const glm::dvec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
};

struct Emitter {
  std::array<glm::dvec3, 3> v;
  glm::dvec3 normal{0.0};
  glm::dvec3 emission{0.0};
  uint32_t global_triangle = 0;
};

// The scene flattened once for all rays: triangle offsets per mesh and the emitters.
struct Prepared {
  std::vector<uint32_t> first_triangle;  // per mesh
  std::vector<Emitter> emitters;
  std::optional<ShadowRays> shadows;
  double scale = 0.0;  // half the bounds' largest side, as GpuSurfaceScene::scale
  Prepared(const SurfaceScene& scene, bool with_shadows) {
    if (with_shadows) shadows.emplace(scene);
    {
      const Bounds b = bounds_of(scene);
      const glm::dvec3 half = b.max - b.center();
      scale = std::max(std::abs(half.x), std::max(std::abs(half.y), std::abs(half.z)));
    }
    uint32_t offset = 0;
    for (const SceneMesh& mesh : scene.meshes) {
      first_triangle.push_back(offset);
      const glm::dvec3& le = scene.materials[mesh.material].emission;
      if (positive(le))
        for (uint32_t j = 0; j < mesh.triangles.size(); ++j) {
          Emitter e;
          for (int k = 0; k < 3; ++k) e.v[size_t(k)] = mesh.positions[mesh.triangles[j][size_t(k)]];
          const glm::dvec3 n = glm::cross(e.v[1] - e.v[0], e.v[2] - e.v[0]);
          const double len = glm::length(n);
          if (!(len > 0.0) || !std::isfinite(len)) continue;  // degenerate: emits nothing
          e.normal = n / len;
          e.emission = le;
          e.global_triangle = offset + j;
          emitters.push_back(e);
        }
      offset += static_cast<uint32_t>(mesh.triangles.size());
    }
  }
};

// A shaded surface point and what its terms add up to.
class PointShader {
 public:
  PointShader(const SurfaceScene& scene, const Prepared& prepared, const DirectLightOptions& options)
      : scene_(scene), prepared_(prepared), options_(options) {}

  DirectLightSample shade(const SurfaceRay& ray, const SurfaceHit& hit) {
    DirectLightSample out;
    const glm::dvec3 dir = glm::normalize(ray.direction);
    if (!hit.hit) {
      out.radiance = scene_.sky.radiance(dir);
      add_rounding(out, max_abs(out.radiance), 2.0);
      return out;
    }
    out.hit = true;
    out.mesh = hit.mesh;
    out.triangle = hit.triangle;
    out.global_triangle = prepared_.first_triangle[hit.mesh] + hit.triangle;
    out.t = hit.t;
    const SceneMesh& mesh = scene_.meshes[hit.mesh];
    const SurfaceMaterial& material = scene_.materials[mesh.material];
    const auto& idx = mesh.triangles[hit.triangle];
    const double b0 = 1.0 - hit.b1 - hit.b2;

    const glm::dvec3 p = hit.position;
    const glm::dvec3 wo = -dir;
    geometric_ = glm::dot(hit.normal, wo) >= 0.0 ? hit.normal : -hit.normal;
    glm::dvec3 n = hit.normal;
    if (!mesh.normals.empty()) {
      const glm::dvec3 s = b0 * mesh.normals[idx[0]] + hit.b1 * mesh.normals[idx[1]] + hit.b2 * mesh.normals[idx[2]];
      const double len = glm::length(s);
      if (len > 0.0 && std::isfinite(len)) n = s / len;
    }
    if (glm::dot(n, geometric_) < 0.0) n = -n;
    if (!(glm::dot(n, wo) > 0.0)) n = geometric_;
    n_ = n;
    basis_ = Basis(n);
    wo_local_ = basis_.local(wo);

    glm::dvec3 albedo = material.albedo;
    if (mesh.color_binding == ColorBinding::PerTriangle) albedo *= mesh.colors[hit.triangle];
    if (mesh.color_binding == ColorBinding::PerVertex)
      albedo *= b0 * mesh.colors[idx[0]] + hit.b1 * mesh.colors[idx[1]] + hit.b2 * mesh.colors[idx[2]];
    params_ = bsdf_params(albedo, material.specular_f0, material.roughness);
    specular_ = params_;
    specular_.albedo = glm::dvec3(0.0);
    has_specular_ = material.specular_f0 != glm::dvec3(0.0);

    glm::dvec3 L(0.0);
    if (glm::dot(hit.normal, wo) > 0.0 && positive(material.emission)) {  // emitters are one-sided
      L += material.emission;
      add_rounding(out, max_of(material.emission), 1.0);
    }
    for (const PointLight& light : scene_.point_lights) {
      const glm::dvec3 to = light.position - p;
      const double d2 = glm::dot(to, to);
      if (!(d2 > 0.0)) continue;
      const glm::dvec3 term = punctual(to / std::sqrt(d2), light.intensity / d2, out);
      if (term != glm::dvec3(0.0) && shadows())
        L += term * visibility(prepared_.shadows->point_light(p, geometric_, out.global_triangle, light.position), out);
      else
        L += term;
    }
    for (const DirectionalLight& light : scene_.directional_lights) {
      const glm::dvec3 wi = -glm::normalize(light.direction);
      const glm::dvec3 term = punctual(wi, light.irradiance, out);
      if (term != glm::dvec3(0.0) && shadows())
        L += term * visibility(prepared_.shadows->directional_light(p, geometric_, out.global_triangle, wi), out);
      else
        L += term;
    }
    for (const Emitter& e : prepared_.emitters) {
      if (e.global_triangle == out.global_triangle) continue;  // a point does not light itself
      const glm::dvec3 term = area(e, p, out);
      if (term != glm::dvec3(0.0) && shadows())
        L += term * visibility(prepared_.shadows->emitter(p, geometric_, n_, out.global_triangle, e.v, e.normal, e.global_triangle), out);
      else
        L += term;
    }
    if (!scene_.sky.black()) {
      const glm::dvec3 sky = params_.albedo * sky_cosine_mean(scene_.sky, n_);
      L += sky;
      add_rounding(out, max_abs(sky), 2.0);
    }
    out.radiance = L;
    return out;
  }

 private:
  static void add_rounding(DirectLightSample& out, double magnitude, double condition) {
    out.rounding_scale += magnitude * condition;
    ++out.terms;
  }

  bool shadows() const { return prepared_.shadows.has_value(); }
  static double visibility(const ShadowVisibility& v, DirectLightSample& out) {
    out.shadow_ambiguous = out.shadow_ambiguous || v.ambiguous;
    out.shadow_rays += v.rays;
    return v.value;
  }

  // How much D's denominator amplifies the rounding of n.h for the pair (wo, wi).
  double ggx_condition(const glm::dvec3& wi_local) const {
    const glm::dvec3 h = glm::normalize(wo_local_ + wi_local);
    const double a2 = specular_.alpha * specular_.alpha;
    const double denom = 1.0 + h.z * h.z * (a2 - 1.0);
    return std::max(1.0, 2.0 / denom);
  }

  // f cos for a unit direction towards a light: 0 below the geometric or the shading horizon.
  bool above(const glm::dvec3& wi, glm::dvec3& wi_local) const {
    if (!(glm::dot(wi, geometric_) > 0.0)) return false;
    wi_local = basis_.local(wi);
    return wi_local.z > 0.0;
  }

  glm::dvec3 punctual(const glm::dvec3& wi, const glm::dvec3& irradiance, DirectLightSample& out) {
    glm::dvec3 wi_local;
    if (!above(wi, wi_local)) return glm::dvec3(0.0);
    const glm::dvec3 term = bsdf_eval(params_, wo_local_, wi_local) * wi_local.z * irradiance;
    const glm::dvec3 diffuse = params_.albedo / kPi * wi_local.z * irradiance;
    add_rounding(out, max_abs(diffuse), 1.0);
    if (has_specular_) add_rounding(out, max_abs(term - diffuse), ggx_condition(wi_local));
    return term;
  }

  glm::dvec3 area(const Emitter& e, const glm::dvec3& p, DirectLightSample& out) {
    // Behind the emitter, or in its plane within PRISMOID_EMITTER_PLANE_EPSILON of the scale.
    if (!(glm::dot(e.normal, p - e.v[0]) > PRISMOID_EMITTER_PLANE_EPSILON * prepared_.scale)) return glm::dvec3(0.0);
    Polygon polygon{e.v[0] - p, e.v[1] - p, e.v[2] - p};
    polygon = clip_to_hemisphere(clip_to_hemisphere(polygon, geometric_), n_);
    if (polygon.size() < 3) return glm::dvec3(0.0);
    const ProjectedSolidAngle psa = projected_solid_angle(polygon, n_);
    glm::dvec3 L = params_.albedo / kPi * e.emission * psa.value;
    add_rounding(out, max_of(params_.albedo) / kPi * max_of(e.emission) * psa.abs_sum, 1.0);
    if (!has_specular_) return L;
    const DirectionalIntegrand f = [&](const glm::dvec3& w) {
      glm::dvec3 w_local;
      if (!above(w, w_local)) return glm::dvec3(0.0);
      return e.emission * bsdf_eval(specular_, wo_local_, w_local) * w_local.z;
    };
    uint32_t nodes = 0;
    const glm::dvec3 rule = subdivision_rule(polygon, options_.subdivision, f, &nodes);
    // The same rule over |value| times its condition: what the rounding of each node weighs.
    const DirectionalIntegrand magnitude = [&](const glm::dvec3& w) {
      glm::dvec3 w_local;
      if (!above(w, w_local)) return glm::dvec3(0.0);
      return glm::dvec3(max_abs(f(w)) * ggx_condition(w_local));
    };
    out.rounding_scale += subdivision_rule(polygon, options_.subdivision, magnitude).x;
    out.terms += nodes;
    if (options_.area_rule == AreaLightRule::Forward) return L + rule;
    return L + adaptive_integral(polygon, f, options_.exact_tolerance * std::max(max_abs(rule), 1e-300));
  }

  const SurfaceScene& scene_;
  const Prepared& prepared_;
  const DirectLightOptions& options_;
  glm::dvec3 geometric_{0.0}, n_{0.0, 0.0, 1.0}, wo_local_{0.0};
  Basis basis_{glm::dvec3(0.0, 0.0, 1.0)};
  BsdfParams params_, specular_;
  bool has_specular_ = false;
};

}  // namespace

glm::dvec3 sky_cosine_mean(const Sky& sky, const glm::dvec3& n) {
  return 0.5 * (sky.top + sky.bottom) + (sky.top - sky.bottom) * (glm::dot(glm::normalize(sky.up), n) / 3.0);
}

std::vector<DirectLightSample> direct_light(const SurfaceScene& scene, std::span<const SurfaceRay> rays,
                                            const DirectLightOptions& options) {
  validate(scene);
  if (options.subdivision == 0) throw InputError("direct light", "the area-light subdivision must be at least 1");
  const std::vector<SurfaceHit> hits = first_hits(scene, rays);
  const Prepared prepared(scene, options.shadows);
  std::vector<DirectLightSample> out(rays.size());
  std::atomic<size_t> next{0};
  constexpr size_t kChunk = 64;
  auto worker = [&] {
    PointShader shader(scene, prepared, options);
    for (size_t begin = next.fetch_add(kChunk); begin < rays.size(); begin = next.fetch_add(kChunk))
      for (size_t i = begin; i < std::min(rays.size(), begin + kChunk); ++i) out[i] = shader.shade(rays[i], hits[i]);
  };
  const unsigned threads = std::max(1u, options.threads ? options.threads : std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  return out;
}

std::vector<DirectLightSample> direct_light_at(const SurfaceScene& scene, std::span<const ShadingPointQuery> points,
                                               const DirectLightOptions& options) {
  validate(scene);
  if (options.subdivision == 0) throw InputError("direct light", "the area-light subdivision must be at least 1");
  for (const ShadingPointQuery& q : points)
    if (q.mesh >= scene.meshes.size() || q.triangle >= scene.meshes[q.mesh].triangles.size())
      throw InputError("direct light", "a surface point names a triangle the scene does not have");
  const Prepared prepared(scene, options.shadows);
  std::vector<DirectLightSample> out(points.size());
  std::atomic<size_t> next{0};
  constexpr size_t kChunk = 64;
  auto worker = [&] {
    PointShader shader(scene, prepared, options);
    for (size_t begin = next.fetch_add(kChunk); begin < points.size(); begin = next.fetch_add(kChunk))
      for (size_t i = begin; i < std::min(points.size(), begin + kChunk); ++i) {
        const ShadingPointQuery& q = points[i];
        const SceneMesh& mesh = scene.meshes[q.mesh];
        const auto& t = mesh.triangles[q.triangle];
        const auto& p = mesh.positions;
        SurfaceHit hit;
        hit.hit = true;
        hit.mesh = q.mesh;
        hit.triangle = q.triangle;
        hit.b1 = q.bary.y;
        hit.b2 = q.bary.z;
        hit.position = q.bary.x * p[t[0]] + q.bary.y * p[t[1]] + q.bary.z * p[t[2]];
        const glm::dvec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
        const double len = glm::length(n);
        hit.normal = len > 0.0 && std::isfinite(len) ? n / len : glm::dvec3(0.0);
        hit.t = glm::length(hit.position - q.eye);
        out[i] = shader.shade(SurfaceRay{q.eye, hit.position - q.eye, 0.0}, hit);
      }
  };
  const unsigned threads = std::max(1u, options.threads ? options.threads : std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  return out;
}

std::vector<float> DirectLightImage::rgb() const {
  std::vector<float> out;
  out.reserve(pixels.size() * 3);
  for (const auto& p : pixels) out.insert(out.end(), {float(p.radiance.x), float(p.radiance.y), float(p.radiance.z)});
  return out;
}

DirectLightImage direct_light_image(const SurfaceScene& scene, const Camera& camera, uint32_t width, uint32_t height,
                                    double offset_x, double offset_y, const DirectLightOptions& options) {
  validate(camera);
  if (width == 0 || height == 0) throw InputError("direct light", "the image size must be positive");
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  std::vector<SurfaceRay> rays;
  rays.reserve(size_t(width) * height);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const glm::dvec3 d = ray_direction(camera, width, height, x + 0.5 + offset_x, y + 0.5 + offset_y);
      rays.push_back({camera.eye, d, camera.near_distance / glm::dot(d, forward)});
    }
  DirectLightImage image;
  image.width = width;
  image.height = height;
  image.pixels = direct_light(scene, rays, options);
  return image;
}

std::vector<glm::dvec3> supersampled_direct_light(const SurfaceScene& scene, const Camera& camera, uint32_t width,
                                                  uint32_t height, uint32_t k, const DirectLightOptions& options) {
  if (k == 0) throw InputError(setting("supersample"), "must be at least 1");
  std::vector<glm::dvec3> sum(size_t(width) * height, glm::dvec3(0.0));
  for (uint32_t j = 0; j < k; ++j)
    for (uint32_t i = 0; i < k; ++i) {
      const DirectLightImage image = direct_light_image(scene, camera, width, height, (i + 0.5) / k - 0.5, (j + 0.5) / k - 0.5, options);
      for (size_t p = 0; p < sum.size(); ++p) sum[p] += image.pixels[p].radiance;
    }
  for (auto& s : sum) s /= double(k) * double(k);
  return sum;
}

}  // namespace prismoid::reference
