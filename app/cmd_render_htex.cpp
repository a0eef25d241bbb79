// `prismoid render SCENE --mode htex`: a surface scene through the Htex object-space shading
// backend (renderer/surface/htex/htex_pass.hpp): shading on per-edge texture quads with shadows,
// gathered per pixel; linear RGB to PFM (or display sRGB to PNG), counters in the stats.
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/cli.hpp"
#include "app/cli_args.hpp"
#include "app/commands.hpp"
#include "app/output_files.hpp"
#include "app/surface_args.hpp"
#include "io/image_io.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/gi/htex_gi.hpp"
#include "renderer/surface/htex/htex_pass.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

bool wants_htex(const std::vector<std::string>& args) {
  for (size_t i = 1; i + 1 < args.size(); ++i)
    if (args[i] == "--mode" && args[i + 1] == "htex") return true;
  return false;
}

int cmd_render_htex(const std::vector<std::string>& args) {
  const ParsedArgs a = parse(args, 1, with_camera({"output", "size", "mode", "quantity", "texels-per-unit", "pool-pages", "stats", "device", "gi",
                                                         "gi-frames", "gi-neighbours", "gi-fallback"}),
                             {"validate", "no-shadows"});
  if (!a.has("output")) throw InputError("render", "--output OUT.pfm|OUT.png is required");
  const std::string output = a.values.at("output");
  OutputFiles files;
  declare_render_files(files, a);
  if (a.has("quantity") && a.values.at("quantity") != "color")
    throw InputError("--quantity", "--mode htex renders linear colour: use --quantity color");
  htex::LayoutOptions layout;
  layout.texels_per_unit = 128.0;
  if (a.has("texels-per-unit")) {
    const std::string& v = a.values.at("texels-per-unit");
    char* end = nullptr;
    layout.texels_per_unit = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0' || !(layout.texels_per_unit > 0.0) || !std::isfinite(layout.texels_per_unit))
      throw InputError("--texels-per-unit", "must be a positive number, got '" + v + "'");
  }
  // GI (ReSTIR GI hosted by the Htex backend, renderer/surface/gi/htex_gi.hpp).
  const std::string gi_mode = a.has("gi") ? a.values.at("gi") : "off";
  if (gi_mode != "off" && gi_mode != "biased" && gi_mode != "unbiased")
    throw InputError("--gi", "must be off, biased or unbiased, got '" + gi_mode + "'");
  const bool gi_on = gi_mode != "off";
  surface::RestirGiSettings gi_settings;
  gi_settings.unbiased = gi_mode == "unbiased";
  uint32_t gi_frames = 8;
  if (a.has("gi-frames")) gi_frames = parse_uint("gi-frames", a.values.at("gi-frames"));
  if (gi_frames == 0) throw InputError("--gi-frames", "at least one frame");
  if (a.has("gi-neighbours")) gi_settings.spatial_neighbours = parse_uint("gi-neighbours", a.values.at("gi-neighbours"));
  if (gi_settings.spatial_neighbours > 16) throw InputError("--gi-neighbours", "at most 16 spatial neighbours");
  if (a.has("gi-fallback")) {
    const std::string& v = a.values.at("gi-fallback");
    if (v != "on" && v != "off") throw InputError("--gi-fallback", "must be on or off, got '" + v + "'");
    gi_settings.fallback = v == "on";
  }
  if (!gi_on && (a.has("gi-frames") || a.has("gi-neighbours") || a.has("gi-fallback")))
    throw InputError("--gi", "--gi-frames, --gi-neighbours and --gi-fallback need --gi biased|unbiased");
  surface::HtexSettings settings;
  if (gi_on) {
    settings.pool_pages = 64;  // GI keeps 256 B per pool texel
    settings.indirect = true;
    settings.sky_ambient = false;
  }
  if (a.has("pool-pages")) settings.pool_pages = parse_uint("pool-pages", a.values.at("pool-pages"));
  if (settings.pool_pages == 0) throw InputError("--pool-pages", "the pool needs at least one page");
  settings.shadows = a.flags.count("no-shadows") == 0;
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{256, 256};
  const SurfaceScene scene = surface_scene_from(a, "htex");
  const Camera camera = surface_camera(a, scene.camera);
  const SurfaceScene lit = with_default_lighting(scene, camera);

  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});
  const surface::GpuSurfaceScene gpu = surface::upload(device, lit);
  const rt::SceneAccel accel(device, lit);
  const surface::HtexGeometry geometry(lit, layout);
  surface::HtexPass pass(device, geometry, settings);
  std::unique_ptr<surface::HtexGi> gi;
  surface::HtexImage image;
  if (gi_on) {
    gi = std::make_unique<surface::HtexGi>(device, pass, gpu, accel);
    image = surface::render_htex_gi(device, pass, *gi, gpu, accel.tlas(), camera, size, gi_frames, gi_settings).image;
  } else {
    image = surface::render_htex(device, pass, gpu, accel.tlas(), camera, size);
  }
  io::FloatImage out;
  out.width = image.width;
  out.height = image.height;
  out.channels = 3;
  out.pixels = image.rgb();
  files.write(output, [&](const std::string& file) { io::write_image(file, out); });

  const surface::HtexCounters& c = image.counters;
  size_t covered = 0;
  for (size_t i = 3; i < image.rgba.size(); i += 4) covered += image.rgba[i] == 1.0f;
  std::cout << "wrote " << output << " (" << size.width << "x" << size.height << ", " << scene.name << ", " << gpu.triangle_count
            << " triangles, htex atlas " << geometry.layout.width() << "x" << geometry.layout.height() << " texels) on " << caps.name << "\n";
  const double total = print_pass_times(std::cout, image.passes);
  std::cout << "  total: " << json_number(total) << " ms GPU\n  covered: " << covered << " pixels; marked " << c.marked_shadels
            << " shadels in " << c.marked_groups << " groups; shaded " << c.shaded_texels << " texels; pool " << settings.pool_pages
            << " pages (" << c.pool_bytes << " bytes)\n";
  if (gi_on)
    std::cout << "  GI " << gi_mode << ": " << gi_frames << " frames averaged, " << gi_settings.spatial_neighbours << " neighbours, fallback "
              << (gi_settings.fallback ? "on" : "off") << "; reservoirs " << gi->reservoir_bytes() << " bytes, persistent layer "
              << gi->persistent_bytes() << " bytes\n";
  if (c.bias_levels > 0) std::cout << "  the pool was too small: level of detail biased by " << c.bias_levels << "\n";
  if (c.overflow)
    std::cout << "  the pool is too small even at the coarsest level: " << c.unallocated_groups << " groups not shaded, " << c.hole_pixels
              << " pixels incomplete (raise --pool-pages or lower --texels-per-unit)\n";
  if (lit.directional_lights.size() != scene.directional_lights.size()) std::cout << "  no lights in the scene: default headlight and sky\n";

  if (a.has("stats")) {
    std::ostringstream js;
    js << ",\n  \"device\": \"" << json_escape(caps.name) << "\",\n  \"driver\": \"" << json_escape(caps.driver_info)
       << "\",\n  \"dataset\": \"" << json_escape(scene.name) << "\",\n  \"mode\": \"htex\",\n  \"quantity\": \"color\",\n  \"width\": "
       << size.width << ",\n  \"height\": " << size.height << ",\n  \"triangles\": " << gpu.triangle_count << ",\n  \"emitters\": "
       << gpu.emitter_count << ",\n  \"gpu_scene_bytes\": " << gpu.bytes << ",\n  \"covered_pixels\": " << covered
       << ",\n  \"shadows\": " << (settings.shadows ? "true" : "false") << ",\n  \"texels_per_unit\": " << json_number(layout.texels_per_unit)
       << ",\n  \"atlas_width\": " << geometry.layout.width() << ",\n  \"atlas_height\": " << geometry.layout.height()
       << ",\n  \"htex_table_bytes\": " << pass.tables().bytes << ",\n  \"pool_pages\": " << settings.pool_pages << ",\n  \"pool_bytes\": "
       << c.pool_bytes << ",\n  \"marked_shadels\": " << c.marked_shadels << ",\n  \"marked_groups\": " << c.marked_groups
       << ",\n  \"marked_groups_unbiased\": " << c.marked_groups_unbiased << ",\n  \"allocated_pages\": " << c.allocated_pages
       << ",\n  \"resident_groups\": " << c.resident_groups << ",\n  \"shaded_shadels\": " << c.shaded_shadels << ",\n  \"shaded_texels\": "
       << c.shaded_texels << ",\n  \"bias_levels\": " << c.bias_levels << ",\n  \"overflow\": " << (c.overflow ? "true" : "false")
       << ",\n  \"unallocated_groups\": " << c.unallocated_groups << ",\n  \"hole_pixels\": " << c.hole_pixels
       << ",\n  \"gi\": \"" << gi_mode << "\"";
    if (gi_on)
      js << ",\n  \"gi_frames\": " << gi_frames << ",\n  \"gi_neighbours\": " << gi_settings.spatial_neighbours
         << ",\n  \"gi_fallback\": " << (gi_settings.fallback ? "true" : "false") << ",\n  \"gi_reservoir_bytes\": " << gi->reservoir_bytes()
         << ",\n  \"gi_persistent_bytes\": " << gi->persistent_bytes() << ",\n  \"gi_persistent_texels\": " << gi->persistent_texels();
    js << ",\n  \"default_lighting\": " << (lit.directional_lights.size() != scene.directional_lights.size() ? "true" : "false");
    files.write(a.values.at("stats"), [&](const std::string& file) {
      write_stats_json(file, js.str(), image.passes, instance.validation_log().count());
    });
  }
  files.commit();
  return validation_exit(instance);
}

}  // namespace prismoid::app
