#include "scene/surface_generators.hpp"

#include <charconv>
#include <cmath>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "scene/generators.hpp"
#include "scene/input_error.hpp"

namespace prismoid {

namespace {

using Quad = std::array<glm::dvec3, 4>;

// Appends quads (corners in order around the quad) as two triangles each: (0,1,2), (0,2,3).
SceneMesh quads_mesh(std::string name, const std::vector<Quad>& quads, uint32_t material) {
  SceneMesh mesh;
  mesh.name = std::move(name);
  mesh.material = material;
  for (const auto& q : quads) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), q.begin(), q.end());
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
  }
  return mesh;
}

}  // namespace

SurfaceScene make_cornell_box() {
  SurfaceScene s;
  s.name = "cornell-box";
  s.materials = {
      {"white", {0.725, 0.71, 0.68}, glm::dvec3(0.0), 1.0, glm::dvec3(0.0)},
      {"red", {0.63, 0.065, 0.05}, glm::dvec3(0.0), 1.0, glm::dvec3(0.0)},
      {"green", {0.14, 0.45, 0.091}, glm::dvec3(0.0), 1.0, glm::dvec3(0.0)},
      {"light", glm::dvec3(0.78), glm::dvec3(0.0), 1.0, {17.0, 12.0, 4.0}},
  };
  const double ly = 548.8 - kCornellLightDrop;
  s.meshes.push_back(quads_mesh("floor", {{{{552.8, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 559.2}, {549.6, 0.0, 559.2}}}}, 0));
  s.meshes.push_back(
      quads_mesh("ceiling", {{{{556.0, 548.8, 0.0}, {556.0, 548.8, 559.2}, {0.0, 548.8, 559.2}, {0.0, 548.8, 0.0}}}}, 0));
  s.meshes.push_back(
      quads_mesh("back wall", {{{{549.6, 0.0, 559.2}, {0.0, 0.0, 559.2}, {0.0, 548.8, 559.2}, {556.0, 548.8, 559.2}}}}, 0));
  s.meshes.push_back(
      quads_mesh("right wall", {{{{0.0, 0.0, 559.2}, {0.0, 0.0, 0.0}, {0.0, 548.8, 0.0}, {0.0, 548.8, 559.2}}}}, 2));
  s.meshes.push_back(
      quads_mesh("left wall", {{{{552.8, 0.0, 0.0}, {549.6, 0.0, 559.2}, {556.0, 548.8, 559.2}, {556.0, 548.8, 0.0}}}}, 1));
  s.meshes.push_back(quads_mesh("short block",
                                {{{{130.0, 165.0, 65.0}, {82.0, 165.0, 225.0}, {240.0, 165.0, 272.0}, {290.0, 165.0, 114.0}}},
                                 {{{290.0, 0.0, 114.0}, {290.0, 165.0, 114.0}, {240.0, 165.0, 272.0}, {240.0, 0.0, 272.0}}},
                                 {{{130.0, 0.0, 65.0}, {130.0, 165.0, 65.0}, {290.0, 165.0, 114.0}, {290.0, 0.0, 114.0}}},
                                 {{{82.0, 0.0, 225.0}, {82.0, 165.0, 225.0}, {130.0, 165.0, 65.0}, {130.0, 0.0, 65.0}}},
                                 {{{240.0, 0.0, 272.0}, {240.0, 165.0, 272.0}, {82.0, 165.0, 225.0}, {82.0, 0.0, 225.0}}}},
                                0));
  s.meshes.push_back(quads_mesh("tall block",
                                {{{{423.0, 330.0, 247.0}, {265.0, 330.0, 296.0}, {314.0, 330.0, 456.0}, {472.0, 330.0, 406.0}}},
                                 {{{423.0, 0.0, 247.0}, {423.0, 330.0, 247.0}, {472.0, 330.0, 406.0}, {472.0, 0.0, 406.0}}},
                                 {{{472.0, 0.0, 406.0}, {472.0, 330.0, 406.0}, {314.0, 330.0, 456.0}, {314.0, 0.0, 456.0}}},
                                 {{{314.0, 0.0, 456.0}, {314.0, 330.0, 456.0}, {265.0, 330.0, 296.0}, {265.0, 0.0, 296.0}}},
                                 {{{265.0, 0.0, 296.0}, {265.0, 330.0, 296.0}, {423.0, 330.0, 247.0}, {423.0, 0.0, 247.0}}}},
                                0));
  // Wound so its normal points down (-y), into the box.
  s.meshes.push_back(quads_mesh("light", {{{{343.0, ly, 227.0}, {343.0, ly, 332.0}, {213.0, ly, 332.0}, {213.0, ly, 227.0}}}}, 3));
  s.camera.eye = {278.0, 273.0, -800.0};
  s.camera.target = {278.0, 273.0, 0.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.fovy_degrees = 2.0 * std::atan(12.5 / 35.0) * 180.0 / 3.14159265358979323846;
  s.camera.near_distance = 1.0;
  return s;
}

SurfaceScene make_furnace(double albedo, double emission, uint32_t subdivisions) {
  if (!(albedo >= 0.0 && albedo < 1.0)) throw InputError("furnace", "albedo must lie in [0, 1)");
  if (!(emission > 0.0) || !std::isfinite(emission)) throw InputError("furnace", "emission must be positive and finite");
  const SurfaceMesh sphere = make_icosphere(glm::dvec3(0.0), 1.0, subdivisions);
  SceneMesh mesh;
  mesh.name = "furnace sphere";
  mesh.positions = sphere.points;
  for (auto t : sphere.triangles) {
    const auto& p = mesh.positions;
    const glm::dvec3 n = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    if (glm::dot(n, p[t[0]] + p[t[1]] + p[t[2]]) > 0.0) std::swap(t[1], t[2]);  // face the centre
    mesh.triangles.push_back(t);
  }
  SurfaceScene s;
  s.name = "furnace:" + std::to_string(albedo);
  s.materials = {{"furnace", glm::dvec3(albedo), glm::dvec3(0.0), 1.0, glm::dvec3(emission)}};
  s.meshes.push_back(std::move(mesh));
  s.camera.eye = glm::dvec3(0.0);
  s.camera.target = {0.0, 0.0, -1.0};
  s.camera.up = {0.0, 1.0, 0.0};
  s.camera.fovy_degrees = 90.0;
  s.camera.near_distance = 1e-3;
  return s;
}

SurfaceMaterial default_surface_material() { return {"default", glm::dvec3(0.8), glm::dvec3(0.04), 0.5, glm::dvec3(0.0)}; }

SurfaceScene make_surface_scene(const SurfaceMesh& surface) {
  SurfaceScene s;
  s.name = surface.name;
  s.materials = {default_surface_material()};
  SceneMesh mesh;
  mesh.name = surface.name;
  mesh.positions = surface.points;
  mesh.triangles = surface.triangles;
  s.meshes.push_back(std::move(mesh));
  s.camera = fit_camera(bounds_of(s));
  return s;
}

bool is_named_surface_scene(const std::string& spec) { return spec == "cornell-box" || spec.rfind("furnace:", 0) == 0; }

namespace {

double parse_number(const std::string& spec, const std::string& text, const char* what) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v))
    throw InputError(spec, std::string(what) + " '" + text + "' is not a number");
  return v;
}

}  // namespace

SurfaceScene make_named_surface_scene(const std::string& spec) {
  if (spec == "cornell-box") return make_cornell_box();
  if (spec.rfind("furnace:", 0) != 0)
    throw InputError(spec, "unknown surface scene: use cornell-box or furnace:A[:LE]");
  const std::string rest = spec.substr(8);
  const size_t colon = rest.find(':');
  const double albedo = parse_number(spec, rest.substr(0, colon), "albedo");
  const double emission = colon == std::string::npos ? 1.0 : parse_number(spec, rest.substr(colon + 1), "emission");
  if (!(albedo >= 0.0 && albedo < 1.0)) throw InputError(spec, "the furnace's albedo must lie in [0, 1)");
  if (!(emission > 0.0)) throw InputError(spec, "the furnace's emission must be positive");
  SurfaceScene s = make_furnace(albedo, emission);
  s.name = spec;
  return s;
}

}  // namespace prismoid
