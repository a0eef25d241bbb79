#include "app/surface_args.hpp"

#include "io/surface_io.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::app {

SurfaceScene surface_scene_from(const ParsedArgs& a, const std::string& mode) {
  if (a.files.size() != 1)
    throw InputError("render", "--mode " + mode + " renders one surface scene: cornell-box, furnace:A[:LE] or a surface file");
  const std::string& file = a.files.front();
  if (is_named_surface_scene(file)) return make_named_surface_scene(file);
  if (io::is_surface_path(file)) return make_surface_scene(io::read_surface(file));
  throw InputError(file, "--mode " + mode + " renders surfaces: cornell-box, furnace:A[:LE], .vtp .stl .obj .ply .off");
}

Camera surface_camera(const ParsedArgs& a, Camera c) {
  if (a.has("eye")) c.eye = parse_vec3("eye", a.values.at("eye"));
  if (a.has("target")) c.target = parse_vec3("target", a.values.at("target"));
  if (a.has("up")) c.up = parse_vec3("up", a.values.at("up"));
  if (a.has("fovy")) c.fovy_degrees = parse_double("fovy", a.values.at("fovy"));
  if (a.has("near")) c.near_distance = parse_double("near", a.values.at("near"));
  validate(c);
  return c;
}

}  // namespace prismoid::app
