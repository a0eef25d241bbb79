// `prismoid render SCENE --mode M` for the surface modes of renderer/surface/surface_modes.hpp,
// drawn through the renderer facade (mixed::SceneRenderer): a GPU mode by its backend, whose frame
// the planner plans; linear RGB to PFM (or display sRGB to PNG), the passes, the plan and the
// backend's counters in the stats. The CPU mode's (the path tracer's) options and report are
// cmd_render_path.cpp's.
#include <algorithm>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "app/cli.hpp"
#include "app/cmd_render_path.hpp"
#include "app/commands.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/frame_stats_writer.hpp"
#include "app/common/output_files.hpp"
#include "app/common/surface_args.hpp"
#include "io/image_io.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::app {

namespace {

bool takes(const surface::SurfaceBackendInfo& backend, const std::string& option) {
  return std::any_of(backend.options.begin(), backend.options.end(), [&](const surface::SurfaceOption& o) { return o.name == option; });
}

// The first mode of the table whose backend takes `option` (nullptr: none does).
const surface::SurfaceMode* mode_taking(const std::string& option) {
  for (const surface::SurfaceMode& m : surface::surface_mode_table())
    if (m.gpu() && takes(*m.backend, option)) return &m;
  return nullptr;
}

// The surface mode drawn on the CPU (the path tracer).
const surface::SurfaceMode& cpu_mode() {
  for (const surface::SurfaceMode& m : surface::surface_mode_table())
    if (!m.gpu()) return m;
  throw std::logic_error("the surface mode table has no CPU mode");
}

// --gi picks the mode of the same backend with that indirect light.
const surface::SurfaceMode& mode_with_gi(const surface::SurfaceMode& mode, const std::string& word) {
  std::vector<std::string> words;
  for (const frame::SurfaceGi gi :
       {frame::SurfaceGi::None, frame::SurfaceGi::RestirBiased, frame::SurfaceGi::RestirUnbiased, frame::SurfaceGi::PathTraced}) {
    const surface::SurfaceMode* m = surface::find_surface_mode(*mode.backend, gi);
    if (!m) continue;
    if (word == frame::surface_gi_name(gi)) return *m;
    words.emplace_back(frame::surface_gi_name(gi));
  }
  std::string list;
  for (size_t i = 0; i < words.size(); ++i) list += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
  throw InputError("--gi", "must be " + list + ", got '" + word + "'");
}

}  // namespace

const surface::SurfaceMode* surface_mode_named(const std::vector<std::string>& args) {
  std::optional<std::string> name;
  for (size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--mode" && i + 1 < args.size()) name = args[i + 1];
    else if (args[i].rfind("--mode=", 0) == 0) name = args[i].substr(7);
  }
  return name ? surface::find_surface_mode(*name) : nullptr;
}

std::string surface_render_help() {
  std::ostringstream out;
  out << "\nSurface modes (FILE: cornell-box, furnace:A[:LE], a surface file .vtp .stl .obj .ply .off, or\n"
         "tiled:N:FILE, N x N copies of one side by side; a file without lights gets a key light and a sky;\n"
         "linear RGB; --size default 256x256; --array, --component,\n"
         "--tf and --tf-range colour a surface file by a data array, as in the window; --max-triangle-pixels P\n"
         "splits triangles until none spans more than P pixels of the first view, as block atlases want):\n";
  for (const surface::SurfaceMode& m : surface::surface_mode_table()) out << "  " << m.name << ": " << m.summary << "\n";
  out << "Their options, by backend (the modes of one backend share them):\n";
  const surface::SurfaceBackendInfo* last = nullptr;
  for (const surface::SurfaceMode& m : surface::surface_mode_table()) {
    if (!m.gpu() || m.backend == last) continue;
    last = m.backend;
    std::string modes;
    for (const surface::SurfaceMode& n : surface::surface_mode_table())
      if (n.backend == m.backend) modes += (modes.empty() ? "" : ", ") + std::string(n.name);
    out << "  " << modes << " (needs " << m.backend->needs << "):\n";
    std::vector<std::pair<std::string, std::string>> rows;
    for (const surface::SurfaceOption& o : m.backend->options)
      rows.emplace_back(std::string("--").append(o.name).append(o.flag ? "" : " ").append(o.value), o.help);
    out << help_table("", 4, rows);
  }
  for (const surface::SurfaceMode& m : surface::surface_mode_table())
    if (!m.gpu()) out << "  " << m.name << " (on the CPU):\n    " << kPathTracerOptionsHelp;
  return out.str();
}

int cmd_render_surface(const std::vector<std::string>& args, const surface::SurfaceMode& chosen) {
  // Every GPU backend's options parse, so that another mode's is refused naming that mode.
  std::vector<std::string> values = with_surface_color(with_camera({"output", "size", "mode", "quantity", "stats", "device"}));
  values.insert(values.end(), kPathTracerOptions.begin(), kPathTracerOptions.end());
  // --no-shadows: the texture-space modes' old spelling of --shadows off, still understood.
  std::vector<std::string> flags = {"validate", "help", "reference-error", "no-shadows"};
  std::vector<std::string> backend_options;
  for (const surface::SurfaceMode& m : surface::surface_mode_table())
    if (m.gpu())
      for (const surface::SurfaceOption& o : m.backend->options) {
        std::vector<std::string>& list = o.flag ? flags : values;
        if (std::find(list.begin(), list.end(), o.name) == list.end()) list.emplace_back(o.name);
        backend_options.emplace_back(o.name);
      }
  const ParsedArgs a = parse(args, 1, values, flags);
  if (a.flags.count("help")) {
    std::cout << render_help();
    return kOk;
  }
  if (a.flags.count("reference-error"))
    throw InputError("--reference-error", chosen.gpu() ? "compares volume modes with their CPU reference; a surface mode's error against the "
                                                         "path tracer is measured by bench (--sweeps surfaces), or by rendering --mode "
                                                         "path-reference and comparing"
                                                       : "--mode " + std::string(chosen.name) + " is the reference itself");
  // Each option belongs to the modes whose backend (or, for the path tracer's, whose CPU mode) takes it.
  for (const std::string& option : kPathTracerOptions)
    if (a.has(option) && chosen.gpu()) throw InputError("--" + option, "is an option of --mode " + std::string(cpu_mode().name));
  if (a.flags.count("no-shadows") && !chosen.gpu())
    throw InputError("--no-shadows", "is an option of --mode " + std::string(mode_taking("shadows")->name));
  surface::SurfaceOptions given;
  auto take = [&](const std::string& name, const std::string& value) {
    if (std::find(backend_options.begin(), backend_options.end(), name) == backend_options.end()) return;
    if (!chosen.gpu() || !takes(*chosen.backend, name))
      throw InputError("--" + name, "is an option of --mode " + std::string(mode_taking(name)->name));
    given[name] = value;
  };
  for (const auto& [name, value] : a.values) take(name, value);
  for (const auto& [name, on] : a.flags) take(name, "");
  const surface::SurfaceMode& mode = given.count("gi") ? mode_with_gi(chosen, given.at("gi")) : chosen;
  given.erase("gi");
  if (mode.gpu()) given = mode.backend->command_options(given, mode.gi);
  const std::string name(mode.name);

  if (!a.has("output")) throw InputError("render", "--output OUT.pfm|OUT.png is required");
  const std::string output = a.values.at("output");
  OutputFiles files;
  declare_render_files(files, a);
  if (a.has("quantity") && a.values.at("quantity") != "color")
    throw InputError("--quantity", "--mode " + name + " renders linear colour: use --quantity color");
  const uint32_t k = given.count("supersample") ? parse_uint("supersample", given.at("supersample")) : 1;
  if (k == 0 || k > 16) throw InputError("--supersample", "must be between 1 and 16 samples per pixel side");
  const uint32_t frames = given.count("frames") ? parse_uint("frames", given.at("frames")) : 1;
  if (frames == 0 || frames > 10000) throw InputError("--frames", "must be between 1 and 10000");
  std::optional<bool> shadows_asked;
  if (a.flags.count("no-shadows")) {
    if (given.count("shadows")) throw InputError("--no-shadows", "is the old spelling of --shadows off: give --shadows alone");
    std::cerr << "prismoid: note: --no-shadows is spelled --shadows off now (every surface mode takes --shadows on|off)\n";
    shadows_asked = false;
  }
  if (given.count("shadows")) {
    const std::string& v = given.at("shadows");
    if (v != "on" && v != "off") throw InputError("--shadows", "'" + v + "' is not on or off");
    shadows_asked = v == "on";
  }
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{256, 256};
  const SurfaceScene loaded = surface_scene_from(a, name);
  const Camera camera = surface_camera(a, loaded);
  const SurfaceScene scene = refined_for_view(a, loaded, camera, size.width, size.height);
  const SurfaceScene lit = with_default_lighting(scene, camera);  // a file without lights is never black

  mixed::SceneSettings scene_settings;
  scene_settings.size = size;
  scene_settings.surface_mode = &mode;
  scene_settings.surface_options = given;
  scene_settings.shadows = shadows_asked;
  scene_settings.supersample = k;
  scene_settings.frames = frames;
  scene_settings.path = path_tracer_settings(a);
  const bool default_lighting = lit.directional_lights.size() != scene.directional_lights.size();
  mixed::SceneRenderer renderer({.surfaces = &lit, .default_lighting = default_lighting}, {.validation = a.flags.count("validate") > 0, .index = parse_device(a)});
  mixed::SceneFrame drawn = renderer.render(camera, scene_settings);
  if (drawn.path) {
    std::ostringstream said;  // printed once the files are in place (cmd_render.cpp says why)
    report_path_traced(a, files, drawn, said);
    files.commit();
    std::cout << said.str();
    return kOk;
  }
  const surface::SurfaceRenderer::Offscreen& image = *drawn.surfaces;
  io::FloatImage out;
  out.width = image.width;
  out.height = image.height;
  out.channels = 3;
  for (size_t i = 0; i < image.rgba.size(); i += 4) out.pixels.insert(out.pixels.end(), {image.rgba[i], image.rgba[i + 1], image.rgba[i + 2]});
  files.write(output, [&](const std::string& file) { io::write_image(file, out); });

  // Printed once the files are in place (cmd_render.cpp says why). "mode" is the mode as given
  // (--gi may have picked another of its backend: the backend's "gi" says which light).
  drawn.stats.surfaces->mode = chosen.name;
  const FrameOutput said{.image = output, .validation_messages = renderer.instance()->validation_log().count()};
  if (a.has("stats"))
    files.write(a.values.at("stats"), [&](const std::string& file) { write_stats(file, frame_json(drawn.stats, said)); });
  files.commit();
  std::cout << frame_text(drawn.stats, said);
  return validation_exit(*renderer.instance());
}

}  // namespace prismoid::app
