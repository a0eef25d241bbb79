// `prismoid render VOLUME SURFACE... --output OUT`: a volume inside its opaque surfaces in one
// frame, through mixed::MixedRenderer on the GPU (renderer/mixed); the verb parses, loads and
// reports, the renderer draws. .png: the composite; .pfm: the volume's quantity (optical depth,
// transmittance) up to the surfaces, or for colour the composite's RGB.
#include <iostream>
#include <memory>
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
#include "app/common/stats_json.hpp"
#include "app/common/volume_options.hpp"
#include "io/image_io.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/vk/device.hpp"
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
  if (a.flags.count("reference-error"))
    throw InputError("--reference-error", "a scene of a volume and surfaces has no CPU reference yet; render the volume alone with "
                                          "--depth-limit to compare it");
  const std::string output = a.values.at("output");
  OutputFiles files;
  declare_render_files(files, a);
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{800, 600};
  const MixedScene scene = mixed_scene_from(a);
  const VolumeChoice& choice = scene.volume;
  const Camera& camera = scene.camera;
  const SurfaceScene& lit = scene.surfaces;
  const bool color = choice.quantity == volume::Quantity::Color;

  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});
  frame::FrameSettings settings = choice.settings;
  if (choice.backend_auto) resolve_auto_backend(settings, device);
  mixed::MixedRenderer renderer(device, choice.mesh, lit);
  const mixed::MixedFrame f = renderer.render(camera, settings, size);

  frame::OffscreenFrame shown = f.volume;  // the composite, where the volume's frame had its display
  shown.display = f.display;
  const io::FloatImage image = frame_image(shown, output, color);
  files.write(output, [&](const std::string& file) { io::write_image(file, image); });
  for (const std::string& w : f.volume.report.warnings) std::cerr << "prismoid: warning: " << w << "\n";

  size_t triangles = 0;
  for (const SceneMesh& m : lit.meshes) triangles += m.triangles.size();
  std::ostringstream said;
  said << "wrote " << output << " (" << size.width << "x" << size.height << ", " << choice.mesh.name << ", " << choice.mesh.tets.size()
       << " cells, with " << lit.name << ", " << triangles << " triangles) on " << caps.name << "\n";
  said << "  volume: --mode " << choice.mode->name << ", backend " << f.volume.report.backend << ", ordering " << f.volume.report.ordering
       << (f.volume.report.order_exact ? " [exact]" : " [approximate]") << "; surfaces: --surface-mode " << scene.surface_mode
       << ", opaque, ending the volume's rays\n";
  const double total = print_pass_times(said, f.passes);
  said << "  total: " << json_number(total) << " ms GPU\n";
  if (a.has("stats")) {
    StatsJson js;
    js["device"] = caps.name;
    js["driver"] = caps.driver_info;
    js["dataset"] = choice.mesh.name;
    js["cells"] = choice.mesh.tets.size();
    js["surfaces"] = lit.name;
    js["triangles"] = triangles;
    js["mode"] = std::string(choice.mode->name);
    js["surface_mode"] = scene.surface_mode;
    js["quantity"] = quantity_name(choice.quantity);
    js["width"] = size.width;
    js["height"] = size.height;
    js["backend"] = f.volume.report.backend;
    js["ordering"] = f.volume.report.ordering;
    js["order_exact"] = f.volume.report.order_exact;
    js["passes"] = passes_json(f.passes);
    add_plan(js, f.volume.report.plan);
    js["gpu_ms_total"] = total;
    js["warnings"] = f.volume.report.warnings;
    js["validation_messages"] = instance.validation_log().count();
    files.write(a.values.at("stats"), [&](const std::string& file) { write_stats(file, js); });
  }
  files.commit();
  std::cout << said.str();
  return validation_exit(instance);
}

}  // namespace prismoid::app
