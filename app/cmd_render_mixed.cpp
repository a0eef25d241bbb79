// `prismoid render VOLUME SURFACE... --output OUT`: a volume inside its opaque surfaces in one
// frame, through the renderer facade (mixed::SceneRenderer: on the GPU or, with --mode reference, on
// the CPU in double precision); the verb parses, loads and reports, the renderer draws. .png: the composite; .pfm: the volume's quantity (optical depth,
// transmittance) up to the surfaces, or for colour the composite's RGB.
#include <chrono>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/backend_cache.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/frame_image.hpp"
#include "app/common/mixed_args.hpp"
#include "app/common/output_files.hpp"
#include "app/common/reference_accuracy.hpp"
#include "app/common/stats_json.hpp"
#include "app/common/volume_options.hpp"
#include "io/image_io.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

bool mixed_scene_named(const std::vector<std::string>& args) { return names_mixed_scene(args, kRenderFlags); }

int cmd_render_mixed(const std::vector<std::string>& args) {
  std::vector<std::string> values = with_camera({"output", "stats", "size", "device"});
  values.insert(values.end(), kVolumeOptions.begin(), kVolumeOptions.end());
  values.insert(values.end(), kMixedSceneOptions.begin(), kMixedSceneOptions.end());
  const ParsedArgs a = parse(args, 1, values, kRenderFlags);
  if (a.flags.count("help")) {
    std::cout << render_help();
    return kOk;
  }
  if (!a.has("output")) throw InputError("render", "--output OUT.png|OUT.pfm is required");
  const std::string output = a.values.at("output");
  OutputFiles files;
  declare_render_files(files, a);
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{800, 600};
  const MixedScene scene = mixed_scene_from(a);
  const VolumeChoice& choice = scene.volume;
  const Camera& camera = scene.camera;
  const SurfaceScene& lit = scene.surfaces;
  const volume::Quantity quantity = choice.quantity;
  const bool color = quantity == volume::Quantity::Color;
  if (!choice.mode->gpu() && a.flags.count("reference-error"))
    throw InputError("--reference-error", "--mode " + std::string(choice.mode->name) + " is the reference itself");
  if (a.flags.count("reference-error") && surface::find_surface_mode(scene.surface_mode)->gi != frame::SurfaceGi::None)
    throw InputError("--reference-error", "the mixed scene's reference lights the surfaces directly, and --surface-mode " +
                                              scene.surface_mode + " adds indirect light; measure its error with `bench --sweeps surfaces`");

  mixed::SceneSettings scene_settings;
  scene_settings.size = size;
  scene_settings.volume_mode = choice.mode;
  scene_settings.volume = choice.settings;
  scene_settings.volume_backend_auto = choice.backend_auto;
  scene_settings.surface_mode = surface::find_surface_mode(scene.surface_mode);
  scene_settings.shadows = scene.shadows;
  mixed::SceneRenderer renderer({.volume = &choice.mesh, .surfaces = &lit},
                                {.validation = a.flags.count("validate") > 0, .index = parse_device(a)}, resolve_auto_backend);
  const mixed::SceneFrame drawn = renderer.render(camera, scene_settings);
  const mixed::MixedFrame& f = *drawn.mixed;
  const bool cpu = !drawn.gpu;
  const std::string& device_name = drawn.device;
  const std::string& driver = drawn.driver;
  const vk::Instance* instance = renderer.instance();
  const size_t validation_messages = instance ? instance->validation_log().count() : 0;

  // The composite, where the volume's frame had its display.
  const auto shown = [](const mixed::MixedFrame& m) {
    frame::OffscreenFrame s = m.volume;
    s.display = m.display;
    return s;
  };
  // What the image's accuracy is: the same mixed frame on the CPU (renderer/mixed/mixed_reference).
  std::optional<ReferenceAccuracy> accuracy;
  if (a.flags.count("reference-error")) {
    const auto start = std::chrono::steady_clock::now();
    const mixed::SceneFrame ref = renderer.reference(camera, scene_settings, drawn);
    accuracy = measure_accuracy(shown(f), shown(*ref.mixed), quantity,
                                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }

  const io::FloatImage image = frame_image(shown(f), output, color);
  files.write(output, [&](const std::string& file) { io::write_image(file, image); });
  for (const std::string& w : f.volume.report.warnings) std::cerr << "prismoid: warning: " << w << "\n";

  size_t triangles = 0;
  for (const SceneMesh& m : lit.meshes) triangles += m.triangles.size();
  std::ostringstream said;
  said << "wrote " << output << " (" << size.width << "x" << size.height << ", " << choice.mesh.name << ", " << choice.mesh.tets.size()
       << " cells, with " << lit.name << ", " << triangles << " triangles) on " << device_name << "\n";
  said << "  volume: --mode " << choice.mode->name;
  if (!cpu) said << ", backend " << f.volume.report.backend;
  said << ", ordering " << f.volume.report.ordering << (f.volume.report.order_exact ? " [exact]" : " [approximate]")
       << "; surfaces: " << (cpu ? "direct light (forward's reference)" : "--surface-mode " + scene.surface_mode)
       << (f.shadows ? " with shadows" : " without shadows") << ", opaque, ending the volume's rays\n";
  const double total = print_pass_times(said, f.passes);
  if (!f.passes.empty()) said << "  total: " << json_number(total) << " ms GPU\n";
  for (const vk::PassTiming& p : f.cpu_passes) said << "  " << p.name << ": " << json_number(p.gpu_ms) << " ms CPU\n";
  if (accuracy)
    print_accuracy(said, *accuracy, color,
                   std::string("double precision, exact per-pixel order, the surfaces' direct light") + (f.shadows ? " with shadows" : ""));
  if (a.has("stats")) {
    StatsJson js;
    js["device"] = device_name;
    js["driver"] = driver;
    js["dataset"] = choice.mesh.name;
    js["cells"] = choice.mesh.tets.size();
    js["surfaces"] = lit.name;
    js["triangles"] = triangles;
    js["mode"] = std::string(choice.mode->name);
    js["surface_mode"] = f.surface_mode;
    js["shadows"] = f.shadows;
    js["quantity"] = quantity_name(quantity);
    js["width"] = size.width;
    js["height"] = size.height;
    if (!cpu) js["backend"] = f.volume.report.backend;
    js["ordering"] = f.volume.report.ordering;
    js["order_exact"] = f.volume.report.order_exact;
    js["passes"] = passes_json(f.passes);
    js["cpu_passes"] = cpu_passes_json(f.cpu_passes);
    add_plan(js, f.plan);
    js["gpu_ms_total"] = total;
    js["warnings"] = f.volume.report.warnings;
    js["validation_messages"] = validation_messages;
    if (accuracy) add_accuracy(js, *accuracy, color);
    files.write(a.values.at("stats"), [&](const std::string& file) { write_stats(file, js); });
  }
  files.commit();
  std::cout << said.str();
  return instance ? validation_exit(*instance) : kOk;
}

}  // namespace prismoid::app
