#pragma once
// Surface scenes for the forward and direct-light tests: a sphere lit by a point light, a
// directional light and a small emissive quad facing it. The sphere is convex and the quad sits
// outside the camera's view and out of the other lights' way, so nothing occludes any light
// from a visible sphere point: direct light without shadows is the exact direct light there.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "scene/generators.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::test {

// An icosphere wound outwards; smooth: per-vertex normals (the sphere's), else flat.
inline SceneMesh sphere_mesh(const glm::dvec3& center, double radius, uint32_t subdivisions, bool smooth, uint32_t material) {
  const SurfaceMesh s = make_icosphere(center, radius, subdivisions);
  SceneMesh mesh;
  mesh.name = "sphere";
  mesh.material = material;
  mesh.positions = s.points;
  for (auto t : s.triangles) {
    const auto& p = mesh.positions;
    const glm::dvec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    if (glm::dot(n, p[t[0]] + p[t[1]] + p[t[2]] - 3.0 * center) < 0.0) std::swap(t[1], t[2]);
    mesh.triangles.push_back(t);
  }
  if (smooth)
    for (const auto& p : mesh.positions) mesh.normals.push_back(glm::normalize(p - center));
  return mesh;
}

// A square of side `size` centred at `center`, wound so that its front faces `target`.
inline SceneMesh facing_quad(const glm::dvec3& center, const glm::dvec3& target, double size, uint32_t material) {
  const glm::dvec3 n = glm::normalize(target - center);
  const glm::dvec3 a = glm::normalize(glm::cross(n, std::abs(n.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 b = glm::cross(n, a);
  const double h = 0.5 * size;
  SceneMesh mesh;
  mesh.name = "quad light";
  mesh.material = material;
  mesh.positions = {center - h * a - h * b, center + h * a - h * b, center + h * a + h * b, center - h * a + h * b};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  if (glm::dot(glm::cross(mesh.positions[1] - mesh.positions[0], mesh.positions[2] - mesh.positions[0]), n) < 0.0)
    mesh.triangles = {{0, 2, 1}, {0, 3, 2}};
  return mesh;
}

enum class Lights { Point, Directional, Area, All };

struct SphereSceneOptions {
  bool smooth = true;
  bool ggx = false;        // GGX material (F0 0.5, roughness 0.5) over albedo 0.3; else diffuse albedo 0.7
  double roughness = 0.5;
  Lights lights = Lights::All;
  bool sky = false;        // a gradient sky (top 0.3, bottom 0.1)
  uint32_t subdivisions = 3;
};

inline Camera sphere_camera() {
  Camera c;
  c.eye = {0.0, 0.0, 4.0};
  c.target = {0.0, 0.0, 0.0};
  c.up = {0.0, 1.0, 0.0};
  c.fovy_degrees = 40.0;
  c.near_distance = 0.1;
  return c;
}

inline SurfaceScene sphere_scene(const SphereSceneOptions& o = {}) {
  SurfaceScene s;
  s.name = "lit sphere";
  SurfaceMaterial m;
  m.name = o.ggx ? "ggx" : "diffuse";
  m.albedo = glm::dvec3(o.ggx ? 0.3 : 0.7);
  m.specular_f0 = glm::dvec3(o.ggx ? 0.5 : 0.0);
  m.roughness = o.roughness;
  SurfaceMaterial light{"quad light", glm::dvec3(0.0), glm::dvec3(0.0), 1.0, {8.0, 6.0, 4.0}};
  s.materials = {m, light};
  s.meshes.push_back(sphere_mesh(glm::dvec3(0.0), 1.0, o.subdivisions, o.smooth, 0));
  const bool all = o.lights == Lights::All;
  if (all || o.lights == Lights::Point) s.point_lights.push_back({{2.0, 2.0, 3.0}, {6.0, 5.0, 4.0}});
  if (all || o.lights == Lights::Directional) s.directional_lights.push_back({{-1.0, -0.3, -0.6}, {1.5, 1.2, 1.0}});
  // Left of the sphere, outside the camera's view, facing the sphere's centre.
  if (all || o.lights == Lights::Area) s.meshes.push_back(facing_quad({-1.8, 0.5, 1.2}, glm::dvec3(0.0), 0.5, 1));
  if (o.sky) s.sky = Sky{glm::dvec3(0.3), glm::dvec3(0.1), {0.0, 1.0, 0.0}};
  s.camera = sphere_camera();
  return s;
}

// A horizontal square of side `size` at height y, centred at (cx, cz), wound upwards (+y).
inline SceneMesh horizontal_quad(const std::string& name, double cx, double y, double cz, double size, uint32_t material) {
  const double h = 0.5 * size;
  SceneMesh mesh;
  mesh.name = name;
  mesh.material = material;
  mesh.positions = {{cx - h, y, cz - h}, {cx - h, y, cz + h}, {cx + h, y, cz + h}, {cx + h, y, cz - h}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

// Shadows with a known umbra: a diffuse floor (side 4 at y = 0, centred at the origin), a
// square occluder of side 1 at height 1 above (0.3, 0.2), a gradient sky as ambient light and
// one light: a point light at (0.4, 3, 0.3) or a directional light travelling along
// (-0.25, -1, 0.15). Seen from above and to the side.
enum class ShadowLight { Point, Directional };
inline constexpr double kOccluderX = 0.3, kOccluderZ = 0.2, kOccluderY = 1.0, kOccluderSize = 1.0;
inline const glm::dvec3 kShadowPointLight{0.4, 3.0, 0.3};
inline const glm::dvec3 kShadowDirection{-0.25, -1.0, 0.15};
inline SurfaceScene occluder_scene(ShadowLight light) {
  SurfaceScene s;
  s.name = "occluder over a floor";
  s.materials = {{"floor", glm::dvec3(0.6, 0.5, 0.4), glm::dvec3(0.0), 1.0, glm::dvec3(0.0)},
                 {"occluder", glm::dvec3(0.3), glm::dvec3(0.0), 1.0, glm::dvec3(0.0)}};
  s.meshes.push_back(horizontal_quad("floor", 0.0, 0.0, 0.0, 4.0, 0));
  s.meshes.push_back(horizontal_quad("occluder", kOccluderX, kOccluderY, kOccluderZ, kOccluderSize, 1));
  if (light == ShadowLight::Point) s.point_lights.push_back({kShadowPointLight, {9.0, 8.0, 7.0}});
  else s.directional_lights.push_back({kShadowDirection, {1.5, 1.3, 1.1}});
  s.sky = Sky{glm::dvec3(0.3), glm::dvec3(0.1), {0.0, 1.0, 0.0}};
  s.camera.eye = {0.5, 4.5, 4.0};
  s.camera.target = {0.0, 0.0, 0.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.fovy_degrees = 45.0;
  s.camera.near_distance = 0.1;
  return s;
}

// The same scene moved by `offset` (camera included): what far-from-origin data looks like.
inline SurfaceScene translated(SurfaceScene s, const glm::dvec3& offset) {
  for (auto& mesh : s.meshes)
    for (auto& p : mesh.positions) p += offset;
  for (auto& l : s.point_lights) l.position += offset;
  s.camera.eye += offset;
  s.camera.target += offset;
  return s;
}

}  // namespace prismoid::test
