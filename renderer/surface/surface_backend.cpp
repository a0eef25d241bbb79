#include "renderer/surface/surface_backend.hpp"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include <glm/geometric.hpp>

#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"

namespace prismoid::surface {

frame::SurfaceContents surface_contents(const SurfaceScene& scene) {
  frame::SurfaceContents c;
  c.point_lights = uint32_t(scene.point_lights.size());
  c.directional_lights = uint32_t(scene.directional_lights.size());
  c.sky = !scene.sky.black();
  for (const SceneMesh& mesh : scene.meshes) {
    c.triangles += mesh.triangles.size();
    const glm::dvec3& e = scene.materials.at(mesh.material).emission;
    if (!(e.x > 0.0 || e.y > 0.0 || e.z > 0.0)) continue;
    for (const auto& t : mesh.triangles) {
      const double twice_area = glm::length(glm::cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
      c.emissive_triangles += twice_area > 0.0 && std::isfinite(twice_area);
    }
  }
  return c;
}

SharedSurfaceScene::SharedSurfaceScene(const vk::Device& device, const SurfaceScene& scene)
    : device_(device), scene_(scene), gpu_(upload(device, scene)), contents_(surface_contents(scene)) {}

SharedSurfaceScene::~SharedSurfaceScene() = default;

const rt::SceneAccel& SharedSurfaceScene::accel() {
  if (!accel_) accel_ = std::make_unique<rt::SceneAccel>(device_, scene_);  // origin: the bounds centre, as gpu_.origin
  return *accel_;
}

ShadingReuse plan_shading_reuse(const ReuseInputs& in) {
  if (in.first_frame) return {true, "shaded: the first frame of this mode"};
  if (in.settings_changed) return {true, "shaded again: the shadows setting changed"};
  if (in.eye_moved && in.amortized) return {false, "reused while the eye moves: amortized (every n-th frame shades again)"};
  if (in.eye_moved) return {true, "shaded again: the eye moved (the shading depends on it)"};
  return {false, "reused: the eye did not move"};
}

ShadingReuse ReuseHistory::plan(const Camera& camera, bool shadows, bool amortized) const {
  ReuseInputs in;
  in.first_frame = !last_eye_;
  in.settings_changed = last_shadows_ != shadows;
  in.eye_moved = last_eye_ && *last_eye_ != camera.eye;
  in.amortized = amortized;
  return plan_shading_reuse(in);
}

double option_number(const SurfaceOptions& options, const std::string& name, double otherwise, bool positive) {
  const auto it = options.find(name);
  if (it == options.end()) return otherwise;
  const std::string& v = it->second;
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || *end != '\0' || !std::isfinite(d) || (positive && !(d > 0.0)))
    throw InputError(setting(name), std::string("must be a ") + (positive ? "positive " : "") + "number, got '" + v + "'");
  return d;
}

uint32_t option_uint(const SurfaceOptions& options, const std::string& name, uint32_t otherwise) {
  const auto it = options.find(name);
  if (it == options.end()) return otherwise;
  const std::string& text = it->second;
  uint32_t v = 0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) throw InputError(setting(name), "'" + text + "' is not a whole number");
  return v;
}

std::string option_choice(const SurfaceOptions& options, const std::string& name, const std::string& otherwise,
                          const std::vector<std::string>& choices) {
  const auto it = options.find(name);
  if (it == options.end()) return otherwise;
  for (const std::string& c : choices)
    if (c == it->second) return c;
  std::string list;
  for (size_t i = 0; i < choices.size(); ++i) list += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + choices[i];
  throw InputError(setting(name), "must be " + list + ", got '" + it->second + "'");
}

}  // namespace prismoid::surface
