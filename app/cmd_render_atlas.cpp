// `prismoid render SCENE --mode texel|msa`: a surface scene through one of the atlas-based
// texture-space backends: texel shading over a static mip-mapped atlas (renderer/surface/
// texel/texel_pass.hpp) or the meshlet shading atlas (renderer/surface/msa/msa_pass.hpp). Shaded with
// shadows, displayed bilinearly per pixel; linear RGB to PFM (or display sRGB to PNG), counters in
// the stats.
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/cli.hpp"
#include "app/cli_args.hpp"
#include "app/commands.hpp"
#include "app/output_files.hpp"
#include "app/surface_args.hpp"
#include "io/image_io.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/msa/msa_pass.hpp"
#include "renderer/surface/texel/texel_pass.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

std::string atlas_mode(const std::vector<std::string>& args) {
  for (size_t i = 1; i + 1 < args.size(); ++i)
    if (args[i] == "--mode" && (args[i + 1] == "texel" || args[i + 1] == "msa")) return args[i + 1];
  return {};
}

double parse_number(const std::string& option, const std::string& v, bool positive) {
  char* end = nullptr;
  const double d = std::strtod(v.c_str(), &end);
  if (end == v.c_str() || *end != '\0' || !std::isfinite(d) || (positive && !(d > 0.0)))
    throw InputError("--" + option, std::string("must be a ") + (positive ? "positive " : "") + "number, got '" + v + "'");
  return d;
}

// What one frame of either backend gave: the image, its pass timings, and the counters as text
// (for the terminal) and as JSON fields (for the stats).
struct AtlasFrame {
  std::vector<float> rgba;
  std::vector<vk::PassTiming> passes;
  std::string summary, atlas, json;
};

AtlasFrame render_texel_frame(const vk::Device& device, const ParsedArgs& a, const SurfaceScene& lit, const surface::GpuSurfaceScene& gpu,
                              const rt::SceneAccel& accel, const Camera& camera, VkExtent2D size, bool shadows) {
  texel::AtlasSettings atlas_settings;
  if (a.has("texel-density")) atlas_settings.texels_per_unit = parse_number("texel-density", a.values.at("texel-density"), true);
  if (a.has("texel-levels")) atlas_settings.levels = parse_uint("texel-levels", a.values.at("texel-levels"));
  surface::TexelSettings settings;
  if (a.has("mip-bias")) settings.lod_bias = float(parse_number("mip-bias", a.values.at("mip-bias"), false));
  settings.shadows = shadows;
  const texel::TexelAtlas atlas = surface::build_texel_atlas_for(device, lit, atlas_settings);
  surface::TexelPass pass(device, atlas, settings);
  const surface::TexelImage image = surface::render_texel(device, pass, gpu, accel.tlas(), camera, size);
  const surface::TexelCounters& c = image.counters;
  AtlasFrame f{image.rgba, image.passes, {}, {}, {}};
  f.atlas = "texel atlas " + std::to_string(atlas.width) + "x" + std::to_string(atlas.height) + " texels, " + std::to_string(atlas.levels) +
            " levels, " + std::to_string(atlas.charts.size()) + " charts";
  f.summary = "queued " + std::to_string(c.queued_tiles) + " tiles; shaded " + std::to_string(c.shaded_texels) + " texels; atlas memory " +
              std::to_string(c.atlas_bytes) + " bytes" + (c.hole_pixels ? "; " + std::to_string(c.hole_pixels) + " pixels read a texel never shaded" : "");
  std::ostringstream js;
  js << ",\n  \"texels_per_unit\": " << json_number(atlas.texels_per_unit) << ",\n  \"atlas_width\": " << atlas.width << ",\n  \"atlas_height\": "
     << atlas.height << ",\n  \"levels\": " << atlas.levels << ",\n  \"charts\": " << atlas.charts.size() << ",\n  \"mip_bias\": "
     << json_number(settings.lod_bias) << ",\n  \"queued_tiles\": " << c.queued_tiles << ",\n  \"shaded_texels\": " << c.shaded_texels
     << ",\n  \"hole_pixels\": " << c.hole_pixels << ",\n  \"atlas_bytes\": " << c.atlas_bytes;
  f.json = js.str();
  return f;
}

AtlasFrame render_msa_frame(const vk::Device& device, const ParsedArgs& a, const SurfaceScene& lit, const surface::GpuSurfaceScene& gpu,
                            const rt::SceneAccel& accel, const Camera& camera, VkExtent2D size, bool shadows) {
  msa::MeshletSettings meshlet_settings;
  if (a.has("meshlets")) {
    const std::string& v = a.values.at("meshlets");
    if (v != "normal-cone" && v != "meshoptimizer") throw InputError("--meshlets", "must be normal-cone or meshoptimizer, got '" + v + "'");
    meshlet_settings.clustering = v == "meshoptimizer" ? msa::Clustering::Meshoptimizer : msa::Clustering::NormalCone;
  }
  if (a.has("msa-charts")) {
    const std::string& v = a.values.at("msa-charts");
    if (v != "projection" && v != "conformal") throw InputError("--msa-charts", "must be projection or conformal, got '" + v + "'");
    meshlet_settings.parametrization = v == "conformal" ? msa::Parametrization::Conformal : msa::Parametrization::Projection;
  }
  surface::MsaSettings settings;
  settings.shadows = shadows;
  if (a.has("msa-superblocks")) settings.superblocks = parse_uint("msa-superblocks", a.values.at("msa-superblocks"));
  if (a.has("shading-budget")) settings.budget_texels = parse_uint("shading-budget", a.values.at("shading-budget"));
  const msa::MeshletSet meshlets = msa::build_meshlets(lit, meshlet_settings);
  surface::MsaPass pass(device, meshlets, settings);
  const surface::MsaImage image = surface::render_msa(device, pass, gpu, accel.tlas(), camera, size);
  const surface::MsaCounters& c = image.counters;
  AtlasFrame f{image.rgba, image.passes, {}, {}, {}};
  f.atlas = "meshlet atlas " + std::to_string(pass.atlas_width()) + "x" + std::to_string(pass.atlas_height()) + " texels, " +
            std::to_string(meshlets.meshlets.size()) + " meshlets";
  f.summary = std::to_string(c.seen_meshlets) + " meshlets seen, " + std::to_string(c.allocated_blocks) + " blocks allocated (" +
              std::to_string(c.held_texels) + " texels" + (c.budget_factor < 1.0f ? ", budget factor " + json_number(c.budget_factor) : "") +
              "); shaded " + std::to_string(c.shaded_texels) + " texels in " + std::to_string(c.shaded_tiles) + " tiles; atlas memory " +
              std::to_string(c.atlas_bytes) + " bytes" +
              (c.hole_pixels ? "; " + std::to_string(c.hole_pixels) + " pixels without shading (atlas too small: raise --msa-superblocks)" : "");
  std::ostringstream js;
  js << ",\n  \"meshlets\": " << meshlets.meshlets.size() << ",\n  \"clustering\": \""
     << (meshlet_settings.clustering == msa::Clustering::Meshoptimizer ? "meshoptimizer" : "normal-cone") << "\",\n  \"charts\": \""
     << (meshlet_settings.parametrization == msa::Parametrization::Conformal ? "conformal" : "projection")
     << "\",\n  \"conformal_fallbacks\": " << meshlets.conformal_fallbacks << ",\n  \"superblocks\": "
     << settings.superblocks << ",\n  \"shading_budget\": " << settings.budget_texels << ",\n  \"budget_factor\": " << json_number(c.budget_factor)
     << ",\n  \"seen_meshlets\": " << c.seen_meshlets << ",\n  \"allocated_blocks\": " << c.allocated_blocks << ",\n  \"block_texels\": "
     << c.held_texels << ",\n  \"shaded_tiles\": " << c.shaded_tiles << ",\n  \"shaded_texels\": " << c.shaded_texels << ",\n  \"hole_pixels\": "
     << c.hole_pixels << ",\n  \"atlas_bytes\": " << c.atlas_bytes;
  f.json = js.str();
  return f;
}

}  // namespace

bool wants_atlas_mode(const std::vector<std::string>& args) { return !atlas_mode(args).empty(); }

int cmd_render_atlas(const std::vector<std::string>& args) {
  const std::string mode = atlas_mode(args);
  const ParsedArgs a = parse(args, 1, with_camera({"output", "size", "mode", "quantity", "texel-density", "texel-levels", "mip-bias", "meshlets",
                                                   "msa-charts", "msa-superblocks", "shading-budget", "stats", "device"}),
                             {"validate", "no-shadows"});
  for (const char* option : {"texel-density", "texel-levels", "mip-bias"})
    if (mode != "texel" && a.has(option)) throw InputError(std::string("--") + option, "is an option of --mode texel");
  for (const char* option : {"meshlets", "msa-charts", "msa-superblocks", "shading-budget"})
    if (mode != "msa" && a.has(option)) throw InputError(std::string("--") + option, "is an option of --mode msa");
  if (!a.has("output")) throw InputError("render", "--output OUT.pfm|OUT.png is required");
  const std::string output = a.values.at("output");
  OutputFiles files;
  declare_render_files(files, a);
  if (a.has("quantity") && a.values.at("quantity") != "color")
    throw InputError("--quantity", "--mode " + mode + " renders linear colour: use --quantity color");
  const bool shadows = a.flags.count("no-shadows") == 0;
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{256, 256};
  const SurfaceScene scene = surface_scene_from(a, mode);
  const Camera camera = surface_camera(a, scene.camera);
  const SurfaceScene lit = with_default_lighting(scene, camera);

  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});
  const surface::GpuSurfaceScene gpu = surface::upload(device, lit);
  const rt::SceneAccel accel(device, lit);
  const AtlasFrame f = mode == "texel" ? render_texel_frame(device, a, lit, gpu, accel, camera, size, shadows)
                                       : render_msa_frame(device, a, lit, gpu, accel, camera, size, shadows);
  io::FloatImage out;
  out.width = size.width;
  out.height = size.height;
  out.channels = 3;
  for (size_t i = 0; i < f.rgba.size(); i += 4) out.pixels.insert(out.pixels.end(), {f.rgba[i], f.rgba[i + 1], f.rgba[i + 2]});
  files.write(output, [&](const std::string& file) { io::write_image(file, out); });

  size_t covered = 0;
  for (size_t i = 3; i < f.rgba.size(); i += 4) covered += f.rgba[i] == 1.0f;
  std::cout << "wrote " << output << " (" << size.width << "x" << size.height << ", " << scene.name << ", " << gpu.triangle_count << " triangles, "
            << f.atlas << ") on " << caps.name << "\n";
  const double total = print_pass_times(std::cout, f.passes);
  std::cout << "  total: " << json_number(total) << " ms GPU\n  covered: " << covered << " pixels; " << f.summary << "\n";
  if (lit.directional_lights.size() != scene.directional_lights.size()) std::cout << "  no lights in the scene: default headlight and sky\n";

  if (a.has("stats")) {
    std::ostringstream js;
    js << ",\n  \"device\": \"" << json_escape(caps.name) << "\",\n  \"dataset\": \"" << json_escape(scene.name) << "\",\n  \"mode\": \"" << mode
       << "\",\n  \"width\": " << size.width << ",\n  \"height\": " << size.height << ",\n  \"triangles\": " << gpu.triangle_count
       << ",\n  \"covered_pixels\": " << covered << ",\n  \"shadows\": " << (shadows ? "true" : "false") << f.json;
    files.write(a.values.at("stats"), [&](const std::string& file) {
      write_stats_json(file, js.str(), f.passes, instance.validation_log().count());
    });
  }
  files.commit();
  return validation_exit(instance);
}

}  // namespace prismoid::app
