// `prismoid render ... --mode path-reference`: the CPU path tracer's options and its frame's report
// (the frame itself is drawn through the renderer facade by cmd_render_surface.cpp): linear RGB to
// PFM (or display sRGB to PNG), the per-pixel variance where asked.
#include "app/cmd_render_path.hpp"

#include <sstream>

#include "app/cli.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/frame_stats_writer.hpp"
#include "app/common/output_files.hpp"
#include "io/image_io.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/reference/path_tracer.hpp"
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

void report_path_traced(const ParsedArgs& a, OutputFiles& files, const mixed::SceneFrame& drawn, std::ostream& said) {
  const reference::PathTracedImage& image = *drawn.path;
  const std::string& output = a.values.at("output");
  files.write(output, [&](const std::string& file) { io::write_image(file, rgb_image(image, image.mean)); });
  if (a.has("variance"))
    files.write(a.values.at("variance"), [&](const std::string& file) { io::write_pfm(file, rgb_image(image, image.variance)); });
  const FrameOutput out{.image = output};
  if (a.has("stats"))
    files.write(a.values.at("stats"), [&](const std::string& file) { write_stats(file, frame_json(drawn.stats, out)); });
  said << frame_text(drawn.stats, out);
}

}  // namespace prismoid::app
