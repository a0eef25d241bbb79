#include "scene/surface_scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include <glm/geometric.hpp>

#include "scene/input_error.hpp"

namespace prismoid {

glm::dvec3 Sky::radiance(const glm::dvec3& unit_direction) const {
  const double t = 0.5 * (1.0 + glm::dot(unit_direction, glm::normalize(up)));
  return bottom + (top - bottom) * t;
}

bool Sky::black() const { return top == glm::dvec3(0.0) && bottom == glm::dvec3(0.0); }

namespace {

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool in_unit_range(const glm::dvec3& v) {
  return v.x >= 0.0 && v.x <= 1.0 && v.y >= 0.0 && v.y <= 1.0 && v.z >= 0.0 && v.z <= 1.0;
}
bool non_negative(const glm::dvec3& v) { return finite(v) && v.x >= 0.0 && v.y >= 0.0 && v.z >= 0.0; }
bool positive(const glm::dvec3& v) { return v.x > 0.0 || v.y > 0.0 || v.z > 0.0; }

void validate_material(const SurfaceScene& scene, const SurfaceMaterial& m, size_t index) {
  const std::string what = "material " + std::to_string(index) + (m.name.empty() ? "" : " (" + m.name + ")");
  if (!finite(m.albedo) || !in_unit_range(m.albedo)) throw InputError(scene.name, what + ": albedo must lie in [0, 1]");
  if (!finite(m.specular_f0) || !in_unit_range(m.specular_f0))
    throw InputError(scene.name, what + ": specular F0 must lie in [0, 1]");
  if (!(m.roughness >= 0.0 && m.roughness <= 1.0)) throw InputError(scene.name, what + ": roughness must lie in [0, 1]");
  if (!non_negative(m.emission)) throw InputError(scene.name, what + ": emission must be finite and >= 0");
}

void validate_mesh(const SurfaceScene& scene, const SceneMesh& mesh, size_t index) {
  const std::string what = "mesh " + std::to_string(index) + (mesh.name.empty() ? "" : " (" + mesh.name + ")");
  if (mesh.material >= scene.materials.size())
    throw InputError(scene.name, what + ": material index " + std::to_string(mesh.material) + " out of range");
  for (const auto& p : mesh.positions)
    if (!finite(p)) throw InputError(scene.name, what + ": a position is not finite");
  for (const auto& t : mesh.triangles)
    for (uint32_t v : t)
      if (v >= mesh.positions.size())
        throw InputError(scene.name, what + ": triangle index " + std::to_string(v) + " out of range");
  if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
    throw InputError(scene.name, what + ": needs one normal per position or none");
  for (const auto& n : mesh.normals)
    if (!finite(n)) throw InputError(scene.name, what + ": a normal is not finite");
  const size_t expected = mesh.color_binding == ColorBinding::PerVertex     ? mesh.positions.size()
                          : mesh.color_binding == ColorBinding::PerTriangle ? mesh.triangles.size()
                                                                            : 0;
  if (mesh.colors.size() != expected)
    throw InputError(scene.name, what + ": has " + std::to_string(mesh.colors.size()) + " colours where its binding needs " +
                                     std::to_string(expected));
  for (const auto& c : mesh.colors)
    if (!finite(c) || !in_unit_range(c)) throw InputError(scene.name, what + ": colours must lie in [0, 1]");
}

}  // namespace

void validate(const SurfaceScene& scene) {
  if (!scene.meshes.empty() && scene.materials.empty()) throw InputError(scene.name, "has meshes but no material");
  for (size_t i = 0; i < scene.materials.size(); ++i) validate_material(scene, scene.materials[i], i);
  for (size_t i = 0; i < scene.meshes.size(); ++i) validate_mesh(scene, scene.meshes[i], i);
  for (const auto& l : scene.point_lights)
    if (!finite(l.position) || !non_negative(l.intensity))
      throw InputError(scene.name, "a point light needs a finite position and an intensity >= 0");
  for (const auto& l : scene.directional_lights)
    if (!finite(l.direction) || glm::length(l.direction) == 0.0 || !non_negative(l.irradiance))
      throw InputError(scene.name, "a directional light needs a non-zero direction and an irradiance >= 0");
  if (!non_negative(scene.sky.top) || !non_negative(scene.sky.bottom))
    throw InputError(scene.name, "the sky's radiance must be finite and >= 0");
  if (!finite(scene.sky.up) || glm::length(scene.sky.up) == 0.0) throw InputError(scene.name, "the sky's up vector is zero");
}

void validate_float_range(const SurfaceScene& scene) {
  auto check = [&](const glm::dvec3& v, const std::string& what) {
    const double largest = std::max({v.x, v.y, v.z});
    if (largest > kMaxRadiometricValue) {
      char buf[160];
      std::snprintf(buf, sizeof buf, " %.3g is beyond %.3g, float32's largest value over 2^32", largest, kMaxRadiometricValue);
      throw InputError(scene.name, what + buf +
                                       " (the GPU shades and every image stores float32; 2^32 is the headroom kept for the "
                                       "factors geometry, materials, lights and bounces multiply it by)");
    }
  };
  for (size_t i = 0; i < scene.materials.size(); ++i)
    check(scene.materials[i].emission, "material " + std::to_string(i) +
                                           (scene.materials[i].name.empty() ? "" : " (" + scene.materials[i].name + ")") + ": emission");
  for (size_t i = 0; i < scene.point_lights.size(); ++i) check(scene.point_lights[i].intensity, "point light " + std::to_string(i) + ": intensity");
  for (size_t i = 0; i < scene.directional_lights.size(); ++i)
    check(scene.directional_lights[i].irradiance, "directional light " + std::to_string(i) + ": irradiance");
  check(glm::max(scene.sky.top, scene.sky.bottom), "the sky: radiance");
}

Bounds bounds_of(const SurfaceScene& scene) {
  Bounds b;
  b.min = glm::dvec3(std::numeric_limits<double>::infinity());
  b.max = -b.min;
  for (const auto& mesh : scene.meshes)
    for (const auto& p : mesh.positions) {
      b.min = glm::min(b.min, p);
      b.max = glm::max(b.max, p);
    }
  if (!(b.min.x <= b.max.x)) return Bounds{};
  return b;
}

bool has_light(const SurfaceScene& scene) {
  for (const auto& l : scene.point_lights)
    if (positive(l.intensity)) return true;
  for (const auto& l : scene.directional_lights)
    if (positive(l.irradiance)) return true;
  if (!scene.sky.black()) return true;
  for (const auto& mesh : scene.meshes) {
    if (mesh.material >= scene.materials.size() || !positive(scene.materials[mesh.material].emission)) continue;
    for (const auto& t : mesh.triangles) {
      const auto& p = mesh.positions;
      if (glm::length(glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]])) > 0.0) return true;
    }
  }
  return false;
}

glm::dvec3 default_key_direction(const Camera& camera) {
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  return glm::normalize(forward - kKeyDown * up + kKeySide * right);
}

SurfaceScene with_default_lighting(SurfaceScene scene, const Camera& camera) {
  if (has_light(scene)) return scene;
  scene.directional_lights.push_back({default_key_direction(camera), glm::dvec3(std::numbers::pi * kHeadlightScale)});
  scene.sky = Sky{glm::dvec3(kDefaultSkyTop), glm::dvec3(kDefaultSkyBottom), camera.up};
  return scene;
}

}  // namespace prismoid
