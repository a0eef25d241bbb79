#include "app/common/mixed_args.hpp"

#include <algorithm>

#include <glm/common.hpp>

#include "io/image_volume_io.hpp"
#include "io/surface_io.hpp"
#include "io/vdb_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/surface/surface_backend.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::app {

namespace {

bool is_surface_spec(const std::string& s) { return io::is_surface_path(s) || is_named_surface_scene(s); }

// Every surface file's scene in one: meshes, materials (re-indexed) and lights in order; the
// first sky that is not black.
SurfaceScene load_surfaces(const std::vector<std::string>& files) {
  SurfaceScene scene;
  for (const std::string& file : files) {
    SurfaceScene one = is_named_surface_scene(file) ? make_named_surface_scene(file) : make_surface_scene(io::read_surface(file));
    const auto material_base = static_cast<uint32_t>(scene.materials.size());
    for (SceneMesh& m : one.meshes) {
      m.material += material_base;
      scene.meshes.push_back(std::move(m));
    }
    scene.materials.insert(scene.materials.end(), one.materials.begin(), one.materials.end());
    scene.point_lights.insert(scene.point_lights.end(), one.point_lights.begin(), one.point_lights.end());
    scene.directional_lights.insert(scene.directional_lights.end(), one.directional_lights.begin(), one.directional_lights.end());
    if (scene.sky.black()) scene.sky = one.sky;
    scene.name += (scene.name.empty() ? "" : " + ") + one.name;
  }
  validate(scene);
  validate_float_range(scene);
  return scene;
}

}  // namespace

bool files_mix_kinds(const std::vector<std::string>& files) {
  return std::any_of(files.begin(), files.end(), is_surface_spec) && !std::all_of(files.begin(), files.end(), is_surface_spec);
}

bool names_mixed_scene(const std::vector<std::string>& args, const std::vector<std::string>& flags) {
  bool volume = false, surface = false;
  for (size_t i = 1; i < args.size(); ++i) {
    const std::string& s = args[i];
    if (s == "--") {  // the rest are files
      for (size_t j = i + 1; j < args.size(); ++j) (is_surface_spec(args[j]) ? surface : volume) = true;
      break;
    }
    if (s.rfind("--", 0) == 0) continue;
    const std::string& before = args[i - 1];
    const bool value_of_option = i > 1 && before.rfind("--", 0) == 0 && before.find('=') == std::string::npos &&
                                 std::find(flags.begin(), flags.end(), before.substr(2)) == flags.end();
    if (value_of_option) continue;
    (is_surface_spec(s) ? surface : volume) = true;
  }
  return volume && surface;
}

MixedScene mixed_scene_from(const ParsedArgs& a) {
  std::vector<std::string> volumes, surfaces;
  for (const std::string& f : a.files) (is_surface_spec(f) ? surfaces : volumes).push_back(f);
  if (volumes.size() != 1)
    throw InputError(volumes.size() > 1 ? volumes[1] : std::string("render"),
                     "a scene with surfaces takes one volume (merge the others into it first)");
  if (a.has("mode") && surface::find_surface_mode(a.values.at("mode")))
    throw InputError("--mode " + a.values.at("mode"),
                     "in a scene of a volume and surfaces --mode names the volume's mode; name the surfaces' with --surface-mode");
  MixedScene scene;
  if (a.has("surface-mode")) scene.surface_mode = a.values.at("surface-mode");
  const surface::SurfaceMode* mode = surface::find_surface_mode(scene.surface_mode);
  if (!mode) {
    std::string known;
    for (const surface::SurfaceMode& m : surface::surface_mode_table()) known += (known.empty() ? "" : ", ") + std::string(m.name);
    throw InputError("--surface-mode", "'" + scene.surface_mode + "' is not a surface mode (" + known + ")");
  }
  if (const std::string problem = mixed::surface_mode_problem(*mode); !problem.empty()) throw InputError("--surface-mode", problem);
  if (a.has("shadows")) {
    const std::string& v = a.values.at("shadows");
    if (v != "on" && v != "off") throw InputError("--shadows", "'" + v + "' is not on or off");
    scene.shadows = v == "on";
  }
  ParsedArgs volume_args = a;
  volume_args.files = volumes;
  scene.volume = volume_choice(volume_args);
  if (const std::string problem = mixed::mixed_scene_problem(scene.volume.settings.resolve); !problem.empty())
    throw InputError("--mode " + std::string(scene.volume.mode->name), problem + "; with surfaces use an interval mode");
  if (!scene.volume.mode->gpu() && field_of(volume_args))
    throw InputError("--mode " + std::string(scene.volume.mode->name),
                     "the reference of an analytic field marches it, and marching follows no depth limit; with surfaces use an "
                     "interval mode (--reference-error compares it with the mesh's reference)");
  const SurfaceScene read = load_surfaces(surfaces);
  const Bounds v = bounds_of(scene.volume.mesh), s = bounds_of(read);
  scene.camera = camera_from(a, {glm::min(v.min, s.min), glm::max(v.max, s.max)});
  scene.surfaces = with_default_lighting(read, scene.camera);
  scene.default_shadows = surface::surface_contents(scene.surfaces).casts_shadows();
  return scene;
}

}  // namespace prismoid::app
