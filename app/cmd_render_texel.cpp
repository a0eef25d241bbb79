// `prismoid render SCENE --mode texel`: a surface scene through the texel shading backend
// (renderer/surface/texel_pass.hpp): shading queued per 8 x 8 tile of a static mip-mapped atlas,
// shaded with shadows, gathered bilinearly per pixel; linear RGB to PFM (or display sRGB to PNG),
// counters in the stats.
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/cli.hpp"
#include "app/cli_args.hpp"
#include "app/commands.hpp"
#include "app/surface_args.hpp"
#include "io/image_io.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/texel_pass.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

bool wants_texel(const std::vector<std::string>& args) {
  for (size_t i = 1; i + 1 < args.size(); ++i)
    if (args[i] == "--mode" && args[i + 1] == "texel") return true;
  return false;
}

namespace {

double parse_positive(const std::string& option, const std::string& v) {
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || *end != '\0' || !(d > 0.0) || !std::isfinite(d)) throw InputError("--" + option, "must be a positive number, got '" + v + "'");
  return d;
}

double parse_finite(const std::string& option, const std::string& v) {
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || *end != '\0' || !std::isfinite(d)) throw InputError("--" + option, "must be a number, got '" + v + "'");
  return d;
}

}  // namespace

int cmd_render_texel(const std::vector<std::string>& args) {
  const ParsedArgs a = parse(args, 1, with_camera({"output", "size", "mode", "quantity", "texel-density", "texel-levels", "mip-bias", "stats", "device"}),
                             {"validate", "no-shadows"});
  if (!a.has("output")) throw InputError("render", "--output OUT.pfm|OUT.png is required");
  const std::string output = a.values.at("output");
  if (!io::is_supported_image_path(output)) throw InputError(output, "unknown image type: use .png or .pfm");
  if (a.has("quantity") && a.values.at("quantity") != "color")
    throw InputError("--quantity", "--mode texel renders linear colour: use --quantity color");
  texel::AtlasSettings atlas_settings;
  if (a.has("texel-density")) atlas_settings.texels_per_unit = parse_positive("texel-density", a.values.at("texel-density"));
  if (a.has("texel-levels")) atlas_settings.levels = parse_uint("texel-levels", a.values.at("texel-levels"));
  surface::TexelSettings settings;
  if (a.has("mip-bias")) settings.lod_bias = float(parse_finite("mip-bias", a.values.at("mip-bias")));
  settings.shadows = a.flags.count("no-shadows") == 0;
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{256, 256};
  const SurfaceScene scene = surface_scene_from(a, "texel");
  const Camera camera = surface_camera(a, scene.camera);
  const SurfaceScene lit = with_default_lighting(scene, camera);
  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});
  const texel::TexelAtlas atlas = surface::build_texel_atlas_for(device, lit, atlas_settings);
  const surface::GpuSurfaceScene gpu = surface::upload(device, lit);
  const rt::SceneAccel accel(device, lit);
  surface::TexelPass pass(device, atlas, settings);
  const surface::TexelImage image = surface::render_texel(device, pass, gpu, accel.tlas(), camera, size);
  io::FloatImage out;
  out.width = image.width;
  out.height = image.height;
  out.channels = 3;
  for (size_t i = 0; i < image.rgba.size(); i += 4) out.pixels.insert(out.pixels.end(), {image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]});
  io::write_image(output, out);

  const surface::TexelCounters& c = image.counters;
  size_t covered = 0;
  for (size_t i = 3; i < image.rgba.size(); i += 4) covered += image.rgba[i] == 1.0f;
  double total = 0.0;
  for (const auto& p : image.passes) total += p.gpu_ms;
  std::cout << "wrote " << output << " (" << size.width << "x" << size.height << ", " << scene.name << ", " << gpu.triangle_count
            << " triangles, texel atlas " << atlas.width << "x" << atlas.height << " texels, " << atlas.levels << " levels, "
            << atlas.charts.size() << " charts) on " << caps.name << "\n";
  for (const auto& p : image.passes)
    std::cout << "  " << p.name << ": " << (std::isfinite(p.gpu_ms) ? json_number(p.gpu_ms) + " ms" : "no timestamps") << " GPU\n";
  std::cout << "  total: " << json_number(total) << " ms GPU\n  covered: " << covered << " pixels; queued " << c.queued_tiles << " tiles; shaded "
            << c.shaded_texels << " texels; atlas memory " << c.atlas_bytes << " bytes\n";
  if (c.hole_pixels) std::cout << "  " << c.hole_pixels << " pixels read a texel never shaded\n";
  if (lit.directional_lights.size() != scene.directional_lights.size()) std::cout << "  no lights in the scene: default headlight and sky\n";

  if (a.has("stats")) {
    std::ostringstream js;
    js << "{\n  \"device\": \"" << json_escape(caps.name) << "\",\n  \"dataset\": \"" << json_escape(scene.name)
       << "\",\n  \"mode\": \"texel\",\n  \"width\": " << size.width << ",\n  \"height\": " << size.height << ",\n  \"triangles\": "
       << gpu.triangle_count << ",\n  \"covered_pixels\": " << covered << ",\n  \"shadows\": " << (settings.shadows ? "true" : "false")
       << ",\n  \"texels_per_unit\": " << json_number(atlas.texels_per_unit) << ",\n  \"atlas_width\": " << atlas.width
       << ",\n  \"atlas_height\": " << atlas.height << ",\n  \"levels\": " << atlas.levels << ",\n  \"charts\": " << atlas.charts.size()
       << ",\n  \"mip_bias\": " << json_number(settings.lod_bias) << ",\n  \"queued_tiles\": " << c.queued_tiles << ",\n  \"shaded_texels\": "
       << c.shaded_texels << ",\n  \"hole_pixels\": " << c.hole_pixels << ",\n  \"atlas_bytes\": " << c.atlas_bytes << ",\n  \"passes\": [";
    for (size_t i = 0; i < image.passes.size(); ++i)
      js << (i ? ",\n" : "\n") << "    {\"name\": \"" << json_escape(image.passes[i].name) << "\", \"gpu_ms\": " << json_number(image.passes[i].gpu_ms) << "}";
    js << "\n  ],\n  \"gpu_ms_total\": " << json_number(total) << ",\n  \"validation_messages\": " << instance.validation_log().count() << "\n}\n";
    std::ofstream f(a.values.at("stats"));
    if (!f || !(f << js.str())) throw InputError(a.values.at("stats"), "cannot write the stats file");
  }
  return validation_exit(instance);
}

}  // namespace prismoid::app
