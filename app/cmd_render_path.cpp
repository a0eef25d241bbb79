// `prismoid render ... --mode path-reference`: the CPU path tracer's options and its frame's report
// (the frame itself is drawn through the renderer facade by cmd_render_surface.cpp): linear RGB to
// PFM (or display sRGB to PNG), the per-pixel variance where asked.
#include "app/cmd_render_path.hpp"

#include <iostream>
#include <sstream>

#include "app/cli.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/output_files.hpp"
#include "app/common/stats_json.hpp"
#include "app/common/surface_args.hpp"
#include "io/image_io.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/reference/path_tracer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

io::FloatImage rgb_image(const reference::PathTracedImage& r, const std::vector<glm::dvec3>& values) {
  io::FloatImage image;
  image.width = r.width;
  image.height = r.height;
  image.channels = 3;
  for (const auto& v : values) image.pixels.insert(image.pixels.end(), {float(v.x), float(v.y), float(v.z)});
  return image;
}

}  // namespace

const char* const kPathTracerOptionsHelp =
    "--spp N (default 64), --max-bounces N, --seed N, --variance OUT.pfm (per-pixel sample variance)\n";

const std::vector<std::string> kPathTracerOptions = {"spp", "max-bounces", "seed", "variance"};

reference::PathTracerSettings path_tracer_settings(const ParsedArgs& a) {
  reference::PathTracerSettings settings;
  settings.samples_per_pixel = a.has("spp") ? parse_uint("spp", a.values.at("spp")) : 64;
  settings.max_bounces = a.has("max-bounces") ? parse_uint("max-bounces", a.values.at("max-bounces")) : settings.max_bounces;
  settings.seed = a.has("seed") ? parse_uint("seed", a.values.at("seed")) : settings.seed;
  if (settings.samples_per_pixel == 0 || settings.samples_per_pixel > (1u << 20))
    throw InputError("--spp", "must be between 1 and 1048576");
  return settings;
}

void report_path_traced(const ParsedArgs& a, OutputFiles& files, const PathTracedRun& run, std::ostream& said) {
  const SurfaceScene& scene = run.scene;
  const SurfaceScene& lit = run.lit;
  const mixed::SceneFrame& drawn = run.drawn;
  const reference::PathTracerSettings& settings = run.settings;
  const reference::PathTracedImage& image = *drawn.path;
  const std::string& output = a.values.at("output");
  files.write(output, [&](const std::string& file) { io::write_image(file, rgb_image(image, image.mean)); });
  if (a.has("variance"))
    files.write(a.values.at("variance"), [&](const std::string& file) { io::write_pfm(file, rgb_image(image, image.variance)); });
  const auto& c = image.counts;
  said << "wrote " << output << " (" << image.width << "x" << image.height << ", " << scene.name << ", " << settings.samples_per_pixel
       << " samples per pixel, at most " << settings.max_bounces << " bounces) on the CPU path tracer in "
       << json_number(image.seconds) << " s\n"
       << "  " << c.rays << " rays; guards: " << c.zero_pdf << " zero-pdf samples, " << c.non_finite << " non-finite samples, "
       << c.backfacing_normals << " back-facing shading normals, " << c.degenerate_triangles << " degenerate triangles skipped\n";
  if (lit.directional_lights.size() != scene.directional_lights.size()) said << "  no lights in the scene: default key light (it casts shadows) and sky\n";
  if (a.has("stats")) {
    StatsJson js;
    js["device"] = drawn.device;
    js["dataset"] = scene.name;
    js["mode"] = std::string(run.mode.name);
    js["width"] = image.width;
    js["height"] = image.height;
    js["samples_per_pixel"] = settings.samples_per_pixel;
    js["max_bounces"] = settings.max_bounces;
    js["seed"] = settings.seed;
    js["seconds"] = image.seconds;
    js["rays"] = c.rays;
    js["zero_pdf"] = c.zero_pdf;
    js["non_finite"] = c.non_finite;
    js["backfacing_normals"] = c.backfacing_normals;
    js["degenerate_triangles"] = c.degenerate_triangles;
    files.write(a.values.at("stats"), [&](const std::string& file) { write_stats(file, js); });
  }
}

}  // namespace prismoid::app
