#include "renderer/reference/path_tracer.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numbers>
#include <string>
#include <thread>

#include <glm/geometric.hpp>

#include "renderer/reference/surface_bsdf.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/reference/triangle_bvh.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"

namespace prismoid::reference {

glm::dvec3 PathTracedImage::standard_error(size_t pixel) const {
  return glm::sqrt(variance.at(pixel) / double(std::max(samples_per_pixel, 1u)));
}

std::vector<float> PathTracedImage::rgb() const {
  std::vector<float> out;
  out.reserve(mean.size() * 3);
  for (const auto& m : mean) {
    out.push_back(static_cast<float>(m.x));
    out.push_back(static_cast<float>(m.y));
    out.push_back(static_cast<float>(m.z));
  }
  return out;
}

namespace {

constexpr double kPi = std::numbers::pi;
// New rays start this far (relative to the point's largest coordinate plus the scene's
// radius) off their surface along its normal: far above the rounding of a hit point rebuilt
// from barycentrics (a few ulps of the coordinates), far below any feature of a scene.
constexpr double kSpawnOffset = 1e-10;
// Shadow rays stop this fraction short of the light sample, whose own triangle is skipped.
constexpr double kShadowShorten = 1e-9;

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
double mean_of(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }
double max_of(const glm::dvec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
double max_abs(const glm::dvec3& v) { return max_of(glm::abs(v)); }

// SplitMix64's finalizer (Steele, Lea & Flood 2014): a bijective 64-bit mix.
uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// A counter-based stream: the n-th number depends only on (key, n), so each (pixel, sample)
// has its own stream whatever thread renders it.
class SampleRng {
 public:
  SampleRng(uint64_t seed, uint64_t pixel, uint64_t sample)
      : key_(mix64(mix64(seed + 0x9e3779b97f4a7c15ULL) ^ (pixel << 32 | sample))) {}
  double next() {  // uniform in [0, 1)
    ++counter_;
    return static_cast<double>(mix64(key_ + counter_ * 0x9e3779b97f4a7c15ULL) >> 11) * 0x1p-53;
  }

 private:
  uint64_t key_;
  uint64_t counter_ = 0;
};

struct FlatTriangle {
  std::array<glm::dvec3, 3> v;
  glm::dvec3 normal{0.0};  // unit winding normal (zero for a degenerate triangle)
  double area = 0.0;
  uint32_t mesh = 0, local = 0;
};

struct Light {
  enum class Kind { Point, Directional, Triangle } kind;
  uint32_t index;    // into the scene's point/directional lights, or the flat triangles
  double probability;
};

// The scene flattened for tracing: one triangle list, its hierarchy, the light list.
class PreparedScene {
 public:
  explicit PreparedScene(const SurfaceScene& scene) : scene_(scene), bvh_(flatten()) {
    const Bounds b = bounds_of(scene);
    radius_ = std::max(b.radius(), 0.0);
    collect_lights();
  }
  const SurfaceScene& scene() const { return scene_; }
  const TriangleBvh& bvh() const { return bvh_; }
  const FlatTriangle& triangle(uint32_t i) const { return triangles_[i]; }
  const SurfaceMaterial& material_of(uint32_t i) const { return scene_.materials[scene_.meshes[triangles_[i].mesh].material]; }
  const std::vector<Light>& lights() const { return lights_; }
  const std::vector<double>& light_cdf() const { return cdf_; }
  // Probability with which light sampling picks triangle i (0 for a non-emitting one).
  double triangle_light_probability(uint32_t i) const {
    const int32_t l = light_of_triangle_[i];
    return l < 0 ? 0.0 : lights_[size_t(l)].probability;
  }
  double spawn_offset(const glm::dvec3& p) const { return kSpawnOffset * (max_abs(p) + radius_); }

  // The albedo at barycentric (b1, b2) of triangle i: material albedo times the mesh colour.
  glm::dvec3 albedo_at(uint32_t i, double b1, double b2) const {
    const FlatTriangle& t = triangles_[i];
    const SceneMesh& mesh = scene_.meshes[t.mesh];
    const glm::dvec3 albedo = scene_.materials[mesh.material].albedo;
    if (mesh.color_binding == ColorBinding::PerTriangle) return albedo * mesh.colors[t.local];
    if (mesh.color_binding == ColorBinding::PerVertex) {
      const auto& idx = mesh.triangles[t.local];
      return albedo * ((1.0 - b1 - b2) * mesh.colors[idx[0]] + b1 * mesh.colors[idx[1]] + b2 * mesh.colors[idx[2]]);
    }
    return albedo;
  }
  // The interpolated shading normal, or the winding normal for flat meshes (not yet faced).
  glm::dvec3 shading_normal_at(uint32_t i, double b1, double b2) const {
    const FlatTriangle& t = triangles_[i];
    const SceneMesh& mesh = scene_.meshes[t.mesh];
    if (mesh.normals.empty()) return t.normal;
    const auto& idx = mesh.triangles[t.local];
    const glm::dvec3 n = (1.0 - b1 - b2) * mesh.normals[idx[0]] + b1 * mesh.normals[idx[1]] + b2 * mesh.normals[idx[2]];
    const double len = glm::length(n);
    return len > 0.0 && std::isfinite(len) ? n / len : t.normal;
  }

 private:
  std::vector<TriangleBvh::Triangle> flatten() {
    std::vector<TriangleBvh::Triangle> corners;
    for (uint32_t m = 0; m < scene_.meshes.size(); ++m) {
      const SceneMesh& mesh = scene_.meshes[m];
      for (uint32_t j = 0; j < mesh.triangles.size(); ++j) {
        FlatTriangle t;
        for (int k = 0; k < 3; ++k) t.v[size_t(k)] = mesh.positions[mesh.triangles[j][size_t(k)]];
        const glm::dvec3 n = glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
        const double len = glm::length(n);
        if (len > 0.0 && std::isfinite(len) && finite(n / len)) {
          t.normal = n / len;
          t.area = 0.5 * len;
        }
        t.mesh = m;
        t.local = j;
        triangles_.push_back(t);
        corners.push_back(t.v);
      }
    }
    return corners;
  }

  void collect_lights() {
    // Power: pi A Le for a one-sided diffuse emitter, 4 pi I for a point light, the power
    // crossing the scene's bounding disk for a directional light (mean over the channels).
    std::vector<std::pair<Light, double>> found;
    for (uint32_t i = 0; i < scene_.point_lights.size(); ++i)
      found.push_back({{Light::Kind::Point, i, 0.0}, 4.0 * kPi * mean_of(scene_.point_lights[i].intensity)});
    const double disk = kPi * std::max(radius_ * radius_, 1e-300);
    for (uint32_t i = 0; i < scene_.directional_lights.size(); ++i)
      found.push_back({{Light::Kind::Directional, i, 0.0}, disk * mean_of(scene_.directional_lights[i].irradiance)});
    light_of_triangle_.assign(triangles_.size(), -1);
    for (uint32_t i = 0; i < triangles_.size(); ++i)
      if (triangles_[i].area > 0.0)
        found.push_back({{Light::Kind::Triangle, i, 0.0}, kPi * triangles_[i].area * mean_of(material_of(i).emission)});
    double total = 0.0;
    for (const auto& [light, power] : found)
      if (power > 0.0 && std::isfinite(power)) total += power;
    if (!(total > 0.0) || !std::isfinite(total)) return;  // nothing to sample: no next-event estimation
    double running = 0.0;
    for (auto [light, power] : found) {
      if (!(power > 0.0) || !std::isfinite(power)) continue;
      light.probability = power / total;
      if (light.kind == Light::Kind::Triangle) light_of_triangle_[light.index] = static_cast<int32_t>(lights_.size());
      lights_.push_back(light);
      running += power;
      cdf_.push_back(running / total);
    }
    cdf_.back() = 1.0;
  }

  const SurfaceScene& scene_;
  std::vector<FlatTriangle> triangles_;
  TriangleBvh bvh_;
  double radius_ = 0.0;
  std::vector<Light> lights_;
  std::vector<double> cdf_;
  std::vector<int32_t> light_of_triangle_;
};

// An orthonormal frame around a unit normal (Duff et al. 2017, "Building an orthonormal basis,
// revisited").
struct Frame {
  glm::dvec3 t, b, n;
  explicit Frame(const glm::dvec3& normal) : n(normal) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z);
    const double c = n.x * n.y * a;
    t = {1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x};
    b = {c, sign + n.y * n.y * a, -n.y};
  }
  glm::dvec3 to_local(const glm::dvec3& v) const { return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)}; }
  glm::dvec3 to_world(const glm::dvec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

// A surface point as the integrator shades it.
struct ShadingPoint {
  uint32_t triangle = kNoTriangle;
  glm::dvec3 position{0.0};
  glm::dvec3 geometric{0.0};  // unit winding normal turned towards the viewer
  Frame frame{glm::dvec3(0.0, 0.0, 1.0)};
  glm::dvec3 wo_local{0.0};
  BsdfParams bsdf;
  glm::dvec3 spawn{0.0};  // origin for rays leaving on the viewer's side
};

double power_heuristic(double a, double b) {
  const double a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

class Integrator {
 public:
  Integrator(const PreparedScene& scene, const PathTracerSettings& settings, PathTracerCounts& counts)
      : s_(scene), settings_(settings), counts_(counts) {}

  // Radiance arriving at `origin` along -direction. `first`, when given, is the first hit itself
  // (not traced): a point whose radiance towards -direction is wanted.
  glm::dvec3 radiance(glm::dvec3 origin, glm::dvec3 direction, double t_min, SampleRng& rng,
                      const TriangleHit* first = nullptr) const {
    glm::dvec3 result(0.0), throughput(1.0);
    uint32_t from_triangle = kNoTriangle;
    glm::dvec3 from_position = origin;
    double bsdf_pdf_of_ray = 0.0;  // solid-angle pdf with which `direction` was sampled (0: camera ray)
    // Light that reached the eye after `reflections` reflections counts from min_bounces on.
    auto counted = [&](uint32_t reflections) { return reflections >= settings_.min_bounces; };
    for (uint32_t bounce = 0;; ++bounce) {
      TriangleHit hit;
      if (bounce == 0 && first != nullptr) {
        hit = *first;
      } else {
        ++counts_.rays;
        hit = s_.bvh().closest_hit(origin, direction, t_min, std::numeric_limits<double>::infinity(), from_triangle);
      }
      if (!hit.hit()) {
        if (counted(bounce)) result += throughput * s_.scene().sky.radiance(direction);
        break;
      }
      const FlatTriangle& tri = s_.triangle(hit.triangle);
      const glm::dvec3 p = (1.0 - hit.b1 - hit.b2) * tri.v[0] + hit.b1 * tri.v[1] + hit.b2 * tri.v[2];
      if (counted(bounce)) result += throughput * emitted(hit.triangle, p, direction, from_position, bsdf_pdf_of_ray);
      if (bounce >= settings_.max_bounces) break;

      const ShadingPoint sp = shading_point(hit, p, -direction);
      if (max_of(sp.bsdf.albedo) <= 0.0 && max_of(sp.bsdf.specular_f0) <= 0.0) break;  // black: reflects nothing
      if (settings_.light_sampling != LightSampling::BsdfOnly) {
        const glm::dvec3 direct = next_event(sp, rng);  // drawn either way: the streams stay aligned
        if (counted(bounce + 1)) result += throughput * direct;
      }

      const double u_lobe = rng.next(), u1 = rng.next(), u2 = rng.next();
      const auto sample = sample_bsdf(sp.bsdf, sp.wo_local, u_lobe, u1, u2);
      if (!sample) break;
      if (!(sample->pdf > 0.0)) {
        ++counts_.zero_pdf;
        break;
      }
      const glm::dvec3 wi = sp.frame.to_world(sample->wi);
      if (!(glm::dot(wi, sp.geometric) > 0.0)) break;  // below the geometric surface: no reflection
      throughput *= sample->weight;
      if (bounce + 1 > settings_.roulette_after) {
        const double survive = std::min(1.0, max_of(throughput));
        if (!(survive > 0.0) || rng.next() >= survive) break;
        throughput /= survive;
      }
      origin = sp.spawn;
      direction = wi;
      t_min = 0.0;
      from_triangle = sp.triangle;
      from_position = p;
      bsdf_pdf_of_ray = sample->pdf;
    }
    return result;
  }

 private:
  // Radiance the hit triangle emits back along the ray, weighted for the estimator that found it.
  glm::dvec3 emitted(uint32_t triangle, const glm::dvec3& p, const glm::dvec3& direction, const glm::dvec3& from,
                     double bsdf_pdf_of_ray) const {
    const FlatTriangle& tri = s_.triangle(triangle);
    const glm::dvec3& le = s_.material_of(triangle).emission;
    if (le == glm::dvec3(0.0)) return glm::dvec3(0.0);
    const double cos_light = -glm::dot(tri.normal, direction);
    if (!(cos_light > 0.0)) return glm::dvec3(0.0);  // its back: emitters are one-sided
    if (bsdf_pdf_of_ray == 0.0) return le;            // seen from the camera
    switch (settings_.light_sampling) {
      case LightSampling::BsdfOnly: return le;
      case LightSampling::LightOnly: return glm::dvec3(0.0);
      case LightSampling::Mis: break;
    }
    const double d2 = glm::dot(p - from, p - from);
    const double light_pdf = s_.triangle_light_probability(triangle) * d2 / (tri.area * cos_light);
    return le * power_heuristic(bsdf_pdf_of_ray, light_pdf);
  }

  ShadingPoint shading_point(const TriangleHit& hit, const glm::dvec3& p, const glm::dvec3& wo) const {
    ShadingPoint sp;
    sp.triangle = hit.triangle;
    sp.position = p;
    const FlatTriangle& tri = s_.triangle(hit.triangle);
    sp.geometric = glm::dot(tri.normal, wo) >= 0.0 ? tri.normal : -tri.normal;  // two-sided reflection
    glm::dvec3 n = s_.shading_normal_at(hit.triangle, hit.b1, hit.b2);
    if (glm::dot(n, sp.geometric) < 0.0) n = -n;  // per-vertex normals wound against the triangle
    if (!(glm::dot(n, wo) > 0.0)) {
      ++counts_.backfacing_normals;
      n = sp.geometric;
    }
    sp.frame = Frame(n);
    sp.wo_local = sp.frame.to_local(wo);
    const SurfaceMaterial& m = s_.material_of(hit.triangle);
    sp.bsdf = bsdf_params(s_.albedo_at(hit.triangle, hit.b1, hit.b2), m.specular_f0, m.roughness);
    sp.spawn = p + sp.geometric * s_.spawn_offset(p);
    return sp;
  }

  // f(wo, wi) cos(theta_i) for a world direction towards a light, 0 below either surface.
  glm::dvec3 reflected(const ShadingPoint& sp, const glm::dvec3& wi) const {
    if (!(glm::dot(wi, sp.geometric) > 0.0)) return glm::dvec3(0.0);
    const glm::dvec3 wi_local = sp.frame.to_local(wi);
    if (!(wi_local.z > 0.0)) return glm::dvec3(0.0);
    return bsdf_eval(sp.bsdf, sp.wo_local, wi_local) * wi_local.z;
  }

  // One light sample: its contribution (already divided by the sampling density).
  glm::dvec3 next_event(const ShadingPoint& sp, SampleRng& rng) const {
    const auto& lights = s_.lights();
    const double u_pick = rng.next(), u1 = rng.next(), u2 = rng.next();
    if (lights.empty()) return glm::dvec3(0.0);
    const auto& cdf = s_.light_cdf();
    const size_t pick = std::min(size_t(std::upper_bound(cdf.begin(), cdf.end(), u_pick) - cdf.begin()), lights.size() - 1);
    const Light& light = lights[pick];
    switch (light.kind) {
      case Light::Kind::Point: {
        const PointLight& pl = s_.scene().point_lights[light.index];
        const glm::dvec3 to = pl.position - sp.position;
        const double d2 = glm::dot(to, to);
        if (!(d2 > 0.0)) return glm::dvec3(0.0);
        const glm::dvec3 fcos = reflected(sp, to / std::sqrt(d2));
        if (fcos == glm::dvec3(0.0) || shadowed(sp.spawn, pl.position - sp.spawn, 1.0 - kShadowShorten, sp.triangle)) return glm::dvec3(0.0);
        return fcos * pl.intensity / (d2 * light.probability);
      }
      case Light::Kind::Directional: {
        const DirectionalLight& dl = s_.scene().directional_lights[light.index];
        const glm::dvec3 wi = -glm::normalize(dl.direction);
        const glm::dvec3 fcos = reflected(sp, wi);
        if (fcos == glm::dvec3(0.0) || shadowed(sp.spawn, wi, std::numeric_limits<double>::infinity(), sp.triangle))
          return glm::dvec3(0.0);
        return fcos * dl.irradiance / light.probability;
      }
      case Light::Kind::Triangle: {
        const FlatTriangle& lt = s_.triangle(light.index);
        const double su = std::sqrt(u1);  // uniform on the triangle's area
        const glm::dvec3 y = (1.0 - su) * lt.v[0] + (su * (1.0 - u2)) * lt.v[1] + (su * u2) * lt.v[2];
        const glm::dvec3 to = y - sp.position;
        const double d2 = glm::dot(to, to);
        if (!(d2 > 0.0)) return glm::dvec3(0.0);
        const glm::dvec3 wi = to / std::sqrt(d2);
        const double cos_light = -glm::dot(lt.normal, wi);
        if (!(cos_light > 0.0)) return glm::dvec3(0.0);  // the light's back faces us
        const glm::dvec3 fcos = reflected(sp, wi);
        if (fcos == glm::dvec3(0.0)) return glm::dvec3(0.0);
        if (shadowed(sp.spawn, y - sp.spawn, 1.0 - kShadowShorten, sp.triangle, light.index)) return glm::dvec3(0.0);
        const double light_pdf = light.probability * d2 / (lt.area * cos_light);  // solid angle
        double weight = 1.0;
        if (settings_.light_sampling == LightSampling::Mis)
          weight = power_heuristic(light_pdf, bsdf_pdf(sp.bsdf, sp.wo_local, sp.frame.to_local(wi)));
        return fcos * s_.material_of(light.index).emission * (weight / light_pdf);
      }
    }
    return glm::dvec3(0.0);
  }

  bool shadowed(const glm::dvec3& origin, const glm::dvec3& direction, double t_max, uint32_t skip_a,
                uint32_t skip_b = kNoTriangle) const {
    ++counts_.rays;
    return s_.bvh().occluded(origin, direction, 0.0, t_max, skip_a, skip_b);
  }

  const PreparedScene& s_;
  const PathTracerSettings& settings_;
  PathTracerCounts& counts_;
};

void add(PathTracerCounts& into, const PathTracerCounts& c) {
  into.paths += c.paths;
  into.rays += c.rays;
  into.zero_pdf += c.zero_pdf;
  into.non_finite += c.non_finite;
  into.backfacing_normals += c.backfacing_normals;
}

}  // namespace

PathTracedImage path_trace(const SurfaceScene& scene, const Camera& camera, const PathTracerSettings& settings) {
  validate(scene);
  validate(camera);
  if (settings.width == 0 || settings.height == 0) throw InputError("path tracer", "the image size must be positive");
  if (settings.samples_per_pixel == 0) throw InputError("path tracer", setting("spp") + " must be at least 1");
  const auto start = std::chrono::steady_clock::now();
  const PreparedScene prepared(scene);

  PathTracedImage image;
  image.width = settings.width;
  image.height = settings.height;
  image.samples_per_pixel = settings.samples_per_pixel;
  const size_t pixels = size_t(settings.width) * settings.height;
  image.mean.assign(pixels, glm::dvec3(0.0));
  image.variance.assign(pixels, glm::dvec3(0.0));
  image.counts.degenerate_triangles = prepared.bvh().skipped_triangles();

  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  std::atomic<uint32_t> next_row{0};
  std::mutex merge;
  auto worker = [&] {
    PathTracerCounts counts;
    const Integrator integrator(prepared, settings, counts);
    for (uint32_t y = next_row++; y < settings.height; y = next_row++) {
      for (uint32_t x = 0; x < settings.width; ++x) {
        const size_t pixel = size_t(y) * settings.width + x;
        glm::dvec3 mean(0.0), m2(0.0);  // Welford's running mean and sum of squared deviations
        for (uint32_t s = 0; s < settings.samples_per_pixel; ++s) {
          SampleRng rng(settings.seed, pixel, s);
          const double jx = settings.jitter ? rng.next() : 0.5, jy = settings.jitter ? rng.next() : 0.5;
          const glm::dvec3 dir = ray_direction(camera, settings.width, settings.height, x + jx, y + jy);
          const double t_near = camera.near_distance / glm::dot(dir, forward);
          glm::dvec3 value = integrator.radiance(camera.eye, dir, t_near, rng);
          ++counts.paths;
          if (!finite(value)) {
            ++counts.non_finite;
            value = glm::dvec3(0.0);
          }
          const glm::dvec3 delta = value - mean;
          mean += delta / double(s + 1);
          m2 += delta * (value - mean);
        }
        image.mean[pixel] = mean;
        image.variance[pixel] = settings.samples_per_pixel > 1 ? m2 / double(settings.samples_per_pixel - 1) : glm::dvec3(0.0);
      }
    }
    const std::lock_guard lock(merge);
    add(image.counts, counts);
  };
  const unsigned threads = std::max(1u, settings.threads ? settings.threads : std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  image.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return image;
}

glm::dvec3 PointRadiance::standard_error() const { return glm::sqrt(variance / double(std::max(samples, 1u))); }

std::vector<PointRadiance> radiance_leaving(const SurfaceScene& scene, std::span<const SurfacePointQuery> points,
                                            const PathTracerSettings& settings, PathTracerCounts* counts_out) {
  validate(scene);
  if (settings.samples_per_pixel == 0) throw InputError("path tracer", "the path count per point must be at least 1");
  const PreparedScene prepared(scene);
  std::vector<uint32_t> first_of_mesh(scene.meshes.size() + 1, 0);
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    first_of_mesh[m + 1] = first_of_mesh[m] + static_cast<uint32_t>(scene.meshes[m].triangles.size());
  std::vector<TriangleHit> hits(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const SurfacePointQuery& q = points[i];
    const std::string where = "surface point " + std::to_string(i);
    if (q.mesh >= scene.meshes.size() || q.triangle >= scene.meshes[q.mesh].triangles.size())
      throw InputError("path tracer", where + " names no triangle of the scene");
    hits[i].triangle = first_of_mesh[q.mesh] + q.triangle;
    if (!(prepared.triangle(hits[i].triangle).area > 0.0)) throw InputError("path tracer", where + " lies on a zero-area triangle");
    const double len = glm::length(q.wo);
    if (!(len > 0.0) || !std::isfinite(len)) throw InputError("path tracer", where + " has no finite, non-zero direction");
    hits[i].t = 1.0;
    hits[i].b1 = q.b1;
    hits[i].b2 = q.b2;
  }
  std::vector<PointRadiance> out(points.size());
  std::atomic<size_t> next{0};
  std::mutex merge;
  PathTracerCounts total;
  auto worker = [&] {
    PathTracerCounts counts;
    const Integrator integrator(prepared, settings, counts);
    for (size_t i = next++; i < points.size(); i = next++) {
      const glm::dvec3 wo = glm::normalize(points[i].wo);
      const FlatTriangle& t = prepared.triangle(hits[i].triangle);
      const glm::dvec3 p = (1.0 - hits[i].b1 - hits[i].b2) * t.v[0] + hits[i].b1 * t.v[1] + hits[i].b2 * t.v[2];
      glm::dvec3 mean(0.0), m2(0.0);
      for (uint32_t s = 0; s < settings.samples_per_pixel; ++s) {
        SampleRng rng(settings.seed, i, s);
        glm::dvec3 value = integrator.radiance(p + wo, -wo, 0.0, rng, &hits[i]);
        ++counts.paths;
        if (!finite(value)) {
          ++counts.non_finite;
          value = glm::dvec3(0.0);
        }
        const glm::dvec3 delta = value - mean;
        mean += delta / double(s + 1);
        m2 += delta * (value - mean);
      }
      out[i].mean = mean;
      out[i].samples = settings.samples_per_pixel;
      out[i].variance = settings.samples_per_pixel > 1 ? m2 / double(settings.samples_per_pixel - 1) : glm::dvec3(0.0);
    }
    const std::lock_guard lock(merge);
    add(total, counts);
  };
  const unsigned threads = std::max(1u, settings.threads ? settings.threads : std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (counts_out) *counts_out = total;
  return out;
}

std::vector<SurfaceHit> first_hits(const SurfaceScene& scene, std::span<const SurfaceRay> rays) {
  validate(scene);
  const PreparedScene prepared(scene);
  std::vector<SurfaceHit> hits;
  hits.reserve(rays.size());
  for (const auto& r : rays) {
    SurfaceHit out;
    const TriangleHit h = prepared.bvh().closest_hit(r.origin, r.direction, r.t_min, std::numeric_limits<double>::infinity());
    if (h.hit()) {
      const FlatTriangle& t = prepared.triangle(h.triangle);
      out.hit = true;
      out.t = h.t;
      out.position = (1.0 - h.b1 - h.b2) * t.v[0] + h.b1 * t.v[1] + h.b2 * t.v[2];
      out.normal = t.normal;
      out.mesh = t.mesh;
      out.triangle = t.local;
      out.b1 = h.b1;
      out.b2 = h.b2;
    }
    hits.push_back(out);
  }
  return hits;
}

}  // namespace prismoid::reference
