// `prismoid render ... --mode path-reference`: a surface scene through the CPU path tracer
// (renderer/reference/path_tracer.hpp), linear RGB to PFM (or display sRGB to PNG).
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/cli.hpp"
#include "app/cli_args.hpp"
#include "app/commands.hpp"
#include "io/image_io.hpp"
#include "io/surface_io.hpp"
#include "renderer/reference/path_tracer.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::app {

namespace {

SurfaceScene surface_scene_of(const ParsedArgs& a) {
  if (a.files.size() != 1)
    throw InputError("render", "--mode path-reference renders one surface scene: cornell-box, furnace:A[:LE] or a surface file");
  const std::string& file = a.files.front();
  if (is_named_surface_scene(file)) return make_named_surface_scene(file);
  if (io::is_surface_path(file)) return make_surface_scene(io::read_surface(file));
  throw InputError(file, "--mode path-reference renders surfaces: cornell-box, furnace:A[:LE], .vtp .stl .obj .ply .off");
}

// The scene's own camera, with each camera option given replacing its part.
Camera camera_of(const ParsedArgs& a, Camera c) {
  if (a.has("eye")) c.eye = parse_vec3("eye", a.values.at("eye"));
  if (a.has("target")) c.target = parse_vec3("target", a.values.at("target"));
  if (a.has("up")) c.up = parse_vec3("up", a.values.at("up"));
  if (a.has("fovy")) c.fovy_degrees = parse_double("fovy", a.values.at("fovy"));
  if (a.has("near")) c.near_distance = parse_double("near", a.values.at("near"));
  validate(c);
  return c;
}

io::FloatImage rgb_image(const reference::PathTracedImage& r, const std::vector<glm::dvec3>& values) {
  io::FloatImage image;
  image.width = r.width;
  image.height = r.height;
  image.channels = 3;
  for (const auto& v : values) image.pixels.insert(image.pixels.end(), {float(v.x), float(v.y), float(v.z)});
  return image;
}

}  // namespace

bool wants_path_reference(const std::vector<std::string>& args) {
  for (size_t i = 1; i + 1 < args.size(); ++i)
    if (args[i] == "--mode" && args[i + 1] == "path-reference") return true;
  return false;
}

int cmd_render_path_reference(const std::vector<std::string>& args) {
  const ParsedArgs a = parse(args, 1, with_camera({"output", "size", "mode", "spp", "max-bounces", "seed", "variance", "stats"}), {});
  if (!a.has("output")) throw InputError("render", "--output OUT.pfm|OUT.png is required");
  const std::string output = a.values.at("output");
  if (!io::is_supported_image_path(output)) throw InputError(output, "unknown image type: use .png or .pfm");
  const SurfaceScene scene = surface_scene_of(a);
  const Camera camera = camera_of(a, scene.camera);
  const SurfaceScene lit = with_default_lighting(scene, camera);  // a file without lights is never black

  reference::PathTracerSettings settings;
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{256, 256};
  settings.width = size.width;
  settings.height = size.height;
  settings.samples_per_pixel = a.has("spp") ? parse_uint("spp", a.values.at("spp")) : 64;
  settings.max_bounces = a.has("max-bounces") ? parse_uint("max-bounces", a.values.at("max-bounces")) : settings.max_bounces;
  settings.seed = a.has("seed") ? parse_uint("seed", a.values.at("seed")) : settings.seed;
  if (settings.samples_per_pixel == 0 || settings.samples_per_pixel > (1u << 20))
    throw InputError("--spp", "must be between 1 and 1048576");
  const reference::PathTracedImage image = reference::path_trace(lit, camera, settings);

  io::write_image(output, rgb_image(image, image.mean));
  if (a.has("variance")) io::write_pfm(a.values.at("variance"), rgb_image(image, image.variance));
  const auto& c = image.counts;
  std::cout << "wrote " << output << " (" << image.width << "x" << image.height << ", " << scene.name << ", " << settings.samples_per_pixel
            << " samples per pixel, at most " << settings.max_bounces << " bounces) on the CPU path tracer in "
            << json_number(image.seconds) << " s\n"
            << "  " << c.rays << " rays; guards: " << c.zero_pdf << " zero-pdf samples, " << c.non_finite << " non-finite samples, "
            << c.backfacing_normals << " back-facing shading normals, " << c.degenerate_triangles << " degenerate triangles skipped\n";
  if (lit.directional_lights.size() != scene.directional_lights.size()) std::cout << "  no lights in the scene: default headlight and sky\n";
  if (a.has("stats")) {
    std::ostringstream js;
    js << "{\n  \"device\": \"CPU path tracer (double precision)\",\n  \"dataset\": \"" << json_escape(scene.name)
       << "\",\n  \"mode\": \"path-reference\",\n  \"width\": " << image.width << ",\n  \"height\": " << image.height
       << ",\n  \"samples_per_pixel\": " << settings.samples_per_pixel << ",\n  \"max_bounces\": " << settings.max_bounces
       << ",\n  \"seed\": " << settings.seed << ",\n  \"seconds\": " << json_number(image.seconds) << ",\n  \"rays\": " << c.rays
       << ",\n  \"zero_pdf\": " << c.zero_pdf << ",\n  \"non_finite\": " << c.non_finite << ",\n  \"backfacing_normals\": "
       << c.backfacing_normals << ",\n  \"degenerate_triangles\": " << c.degenerate_triangles << "\n}\n";
    std::ofstream out(a.values.at("stats"));
    if (!out || !(out << js.str())) throw InputError(a.values.at("stats"), "cannot write the stats file");
  }
  return kOk;
}

}  // namespace prismoid::app
