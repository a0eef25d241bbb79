// `prismoid render VOLUME SURFACE... --output OUT`: a volume inside its opaque surfaces in one
// frame, through the renderer facade (mixed::SceneRenderer: on the GPU or, with --mode reference, on
// the CPU in double precision); the verb parses, loads and reports, the renderer draws. .png: the composite; .pfm: the volume's quantity (optical depth,
// transmittance) up to the surfaces, or for colour the composite's RGB.
#include <chrono>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/backend_cache.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/frame_image.hpp"
#include "app/common/frame_stats_writer.hpp"
#include "app/common/mixed_args.hpp"
#include "app/common/output_files.hpp"
#include "app/common/reference_accuracy.hpp"
#include "app/common/volume_options.hpp"
#include "io/image_io.hpp"
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

  // Printed once the files are in place (cmd_render.cpp says why).
  const FrameOutput said{.image = output, .validation_messages = validation_messages, .accuracy = accuracy ? &*accuracy : nullptr};
  if (a.has("stats"))
    files.write(a.values.at("stats"), [&](const std::string& file) { write_stats(file, frame_json(drawn.stats, said)); });
  files.commit();
  std::cout << frame_text(drawn.stats, said);
  return instance ? validation_exit(*instance) : kOk;
}

}  // namespace prismoid::app
