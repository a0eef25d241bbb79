#include "app/common/surface_args.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "io/surface_io.hpp"
#include "io/transfer_function_io.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"
#include "scene/surface_refine.hpp"

namespace prismoid::app {

namespace {

// The scalar of each tuple: one component, or the magnitude (the default for vectors).
std::vector<double> scalars_of(const SurfaceArray& array, int component, const std::string& file) {
  if (component >= int(array.components))
    throw InputError("--component", "array '" + array.name + "' of " + file + " has " + std::to_string(array.components) +
                                        " component(s)");
  const size_t tuples = array.values.size() / array.components;
  std::vector<double> s(tuples);
  for (size_t t = 0; t < tuples; ++t) {
    const double* v = &array.values[t * array.components];
    if (component >= 0 || array.components == 1) {
      s[t] = v[std::max(component, 0)];
    } else {
      double sum = 0.0;
      for (uint32_t c = 0; c < array.components; ++c) sum += v[c] * v[c];
      s[t] = std::sqrt(sum);
    }
    if (!std::isfinite(s[t])) throw InputError(file, "array '" + array.name + "' has a non-finite value at tuple " + std::to_string(t));
  }
  return s;
}

}  // namespace

SurfaceArrayColoring array_coloring_from(const ParsedArgs& a) {
  SurfaceArrayColoring c;
  if (a.has("array")) c.array = a.values.at("array");
  if (a.has("component")) {
    if (c.array.empty()) throw InputError("--component", "picks a component of the --array NAME");
    const std::string& v = a.values.at("component");
    c.component = v == "x" || v == "X" ? 0 : v == "y" || v == "Y" ? 1 : v == "z" || v == "Z" ? 2 : v == "magnitude" ? -1
                                                                                                   : int(parse_uint("component", v));
  }
  c.transfer = io::transfer_function_from(a.has("tf") ? a.values.at("tf") : "cool-to-warm");
  if (a.has("tf-range")) {
    if (c.array.empty()) throw InputError("--tf-range", "maps the --array NAME's values: give --array");
    const std::string& text = a.values.at("tf-range");
    const auto comma = text.find(',');
    if (comma == std::string::npos) throw InputError("--tf-range", "expects LO,HI, got '" + text + "'");
    c.range = {parse_double("tf-range", text.substr(0, comma)), parse_double("tf-range", text.substr(comma + 1))};
    if (!(c.range->second > c.range->first)) throw InputError("--tf-range", "HI must be greater than LO");
  }
  return c;
}

void color_by_array(SurfaceScene& scene, const SurfaceMesh& surface, const SurfaceArrayColoring& coloring) {
  if (coloring.array.empty()) return;
  auto find = [&](const std::vector<SurfaceArray>& arrays) {
    return std::find_if(arrays.begin(), arrays.end(), [&](const SurfaceArray& x) { return x.name == coloring.array; });
  };
  const auto point = find(surface.point_arrays);
  const auto cell = find(surface.cell_arrays);
  if (point == surface.point_arrays.end() && cell == surface.cell_arrays.end()) {
    std::string names;
    for (const auto& x : surface.point_arrays) names += (names.empty() ? "" : ", ") + x.name + " (point)";
    for (const auto& x : surface.cell_arrays) names += (names.empty() ? "" : ", ") + x.name + " (cell)";
    throw InputError(surface.name, "has no array '" + coloring.array + "' (" + (names.empty() ? "it has no data arrays" : "arrays: " + names) + ")");
  }
  const bool per_point = point != surface.point_arrays.end();
  const std::vector<double> s = scalars_of(per_point ? *point : *cell, coloring.component, surface.name);
  volume::TransferFunction tf = coloring.transfer;
  if (coloring.range) {
    tf.range_lo = coloring.range->first;
    tf.range_hi = coloring.range->second;
  } else {
    const auto [lo, hi] = std::minmax_element(s.begin(), s.end());
    tf.range_lo = *lo;
    tf.range_hi = *hi > *lo ? *hi : *lo + 1.0;  // a constant array maps to the range's start
  }
  const std::vector<volume::TfSample> samples = volume::breakpoints(tf);
  SceneMesh& mesh = scene.meshes.at(0);
  mesh.colors.clear();
  for (double v : s) mesh.colors.push_back(volume::evaluate(samples, volume::normalized(tf, v)).rgb);
  mesh.color_binding = per_point ? ColorBinding::PerVertex : ColorBinding::PerTriangle;
}

namespace {

// "tiled:N:FILE": N x N copies of FILE's surface side by side in a wall facing the camera (+z),
// a gap of a fifth of the mesh's size between them: a scene of many scans from one, as large as
// a benchmark wants (the FastAtlas comparison's 10^6 triangles and more). Arrays are dropped.
std::optional<SurfaceScene> tiled_scene(const std::string& spec) {
  if (spec.rfind("tiled:", 0) != 0) return std::nullopt;
  const size_t colon = spec.find(':', 6);
  if (colon == std::string::npos) throw InputError(spec, "a tiled scene is tiled:N:FILE (N copies a side)");
  const std::string count = spec.substr(6, colon - 6), file = spec.substr(colon + 1);
  uint32_t n = 0;
  try {
    size_t used = 0;
    const unsigned long v = std::stoul(count, &used);
    if (used != count.size() || v < 1 || v > 64) throw std::out_of_range("n");
    n = uint32_t(v);
  } catch (const std::exception&) {
    throw InputError(spec, "the copies a side must be a whole number from 1 to 64, got '" + count + "'");
  }
  if (!io::is_surface_path(file)) throw InputError(file, "tiled:N:FILE wants a surface file (.vtp .stl .obj .ply .off)");
  const SurfaceMesh one = io::read_surface(file);
  if (one.points.empty()) throw InputError(file, "has no points to tile");
  glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
  for (const glm::dvec3& p : one.points) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::dvec3 size = hi - lo;
  const double step = 1.2 * std::max({size.x, size.y, 1e-30});
  if (uint64_t(one.triangles.size()) * n * n > 0xffffffffull / 3 || uint64_t(one.points.size()) * n * n > 0xffffffffull)
    throw InputError(spec, "too many triangles for one scene");
  SurfaceMesh wall;
  wall.name = one.name + " x" + std::to_string(n * n);
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const glm::dvec3 offset(step * i, step * j, 0.0);
      const uint32_t base = uint32_t(wall.points.size());
      for (const glm::dvec3& p : one.points) wall.points.push_back(p + offset);
      for (const auto& t : one.triangles) wall.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
  SurfaceScene scene = make_surface_scene(wall);
  scene.name = "tiled:" + std::to_string(n) + ":" + one.name;
  return scene;
}

}  // namespace

SurfaceScene surface_scene_from(const ParsedArgs& a, const std::string& mode) {
  if (a.files.size() != 1)
    throw InputError("--mode " + mode, "draws one surface scene: cornell-box, furnace:A[:LE], tiled:N:FILE or a surface file");
  const std::string& file = a.files.front();
  if (std::optional<SurfaceScene> tiled = tiled_scene(file)) {
    if (!array_coloring_from(a).array.empty()) throw InputError(file, "a tiled scene keeps no data arrays for --array");
    return *tiled;
  }
  const SurfaceArrayColoring coloring = array_coloring_from(a);
  if (is_named_surface_scene(file)) {
    if (!coloring.array.empty()) throw InputError(file, "has no data arrays for --array (a built-in scene)");
    return make_named_surface_scene(file);
  }
  if (io::is_surface_path(file)) {
    const SurfaceMesh surface = io::read_surface(file);
    SurfaceScene scene = make_surface_scene(surface);
    color_by_array(scene, surface, coloring);
    return scene;
  }
  throw InputError(file, "--mode " + mode + " renders surfaces: cornell-box, furnace:A[:LE], tiled:N:FILE, .vtp .stl .obj .ply .off");
}

SurfaceScene refined_for_view(const ParsedArgs& a, SurfaceScene scene, const Camera& camera, uint32_t width, uint32_t height) {
  if (!a.has("max-triangle-pixels")) return scene;
  return refine_large_triangles(scene, camera, width, height, parse_double("max-triangle-pixels", a.values.at("max-triangle-pixels")));
}

Camera surface_camera(const ParsedArgs& a, const SurfaceScene& scene) {
  Camera c = scene.camera;
  if (a.has("eye")) c.eye = parse_vec3("eye", a.values.at("eye"));
  if (a.has("target")) c.target = parse_vec3("target", a.values.at("target"));
  if (a.has("up")) c.up = parse_vec3("up", a.values.at("up"));
  c.fovy_degrees = parse_fovy(a, c.fovy_degrees);
  if (a.has("near")) c.near_distance = parse_double("near", a.values.at("near"));
  else if (a.has("eye") || a.has("target")) c.near_distance = near_plane_for(c, bounds_of(scene));
  validate(c);
  return c;
}

}  // namespace prismoid::app
