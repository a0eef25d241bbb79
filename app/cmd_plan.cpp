// `prismoid info FILE --plan`: the frame plan for the volume options, or for a surface scene and
// a surface mode, without a GPU.
#include <iostream>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/backend_cache.hpp"
#include "app/common/mixed_args.hpp"
#include "app/common/surface_args.hpp"
#include "app/common/volume_options.hpp"
#include "renderer/frame/frame_plan.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::app {

namespace {

// A surface frame as the surface renderer plans it: the scene's lights (a file without lights
// gets the default key light (it casts shadows) and sky, as render and the window give it), shadows on where a light
// casts them, on a device that traces rays (without one, the plan skips the shadow rays).
int surface_plan(const ParsedArgs& a, const surface::SurfaceMode& mode) {
  const std::string name(mode.name);
  const SurfaceScene scene = surface_scene_from(a, name);
  const SurfaceScene lit = with_default_lighting(scene, surface_camera(a, scene));
  const frame::SurfaceContents c = surface::surface_contents(lit);
  std::cout << scene.name << ": " << c.triangles << " triangles, " << c.point_lights << " point and " << c.directional_lights
            << " directional lights, " << c.emissive_triangles << " emissive triangles, " << (c.sky ? "a sky" : "no sky")
            << (lit.directional_lights.size() != scene.directional_lights.size() ? " (no lights of its own: the default key light (it casts shadows) and sky)" : "")
            << "; mode " << name << "\n";
  if (!mode.gpu()) {
    std::cout << "plan: " << mode.summary << ", on the CPU (no GPU passes)\n";
    return kOk;
  }
  frame::SurfaceFrameSettings settings;
  settings.mode = name;
  settings.passes = mode.backend->passes;
  settings.gi = mode.gi;
  settings.shadows = true;
  settings.device_traces_rays = true;
  std::cout << "plan (a frame on a device that traces rays; " << mode.backend->name << " needs " << mode.backend->needs << "):\n";
  const frame::FramePlan plan = frame::plan_surface_frame(c, settings);
  for (const frame::PlannedPass& p : plan.passes) std::cout << "  " << p.name << " (" << frame::pass_kind_text(p.kind) << "): " << p.reason << "\n";
  std::cout << "skipped:" << (plan.skipped.empty() ? " none\n" : "\n");
  for (const frame::SkippedPass& s : plan.skipped) std::cout << "  " << s.name << ": " << s.reason << "\n";
  return kOk;
}

void print_plan(const frame::FramePlan& plan, const std::string& indent) {
  for (const frame::PlannedPass& p : plan.passes)
    std::cout << indent << p.name << " (" << frame::pass_kind_text(p.kind) << "): " << p.reason << "\n";
  std::cout << indent.substr(2) << "skipped:" << (plan.skipped.empty() ? " none\n" : "\n");
  for (const frame::SkippedPass& s : plan.skipped)
    std::cout << indent << s.name << ": " << s.reason << "\n";
}

// A volume inside its surfaces (renderer/mixed): the surfaces' forward frame, the volume's frame
// with its rays ended at their depth, and the composite, each with its passes and why.
int mixed_plan(const ParsedArgs& a) {
  const MixedScene scene = mixed_scene_from(a);
  const VolumeChoice& choice = scene.volume;
  const SurfaceScene& lit = scene.surfaces;
  const frame::SurfaceContents c = surface::surface_contents(lit);
  std::cout << choice.mesh.name << ": " << choice.mesh.tets.size() << " cells, mode " << choice.mode->name << ", quantity "
            << quantity_name(choice.quantity) << "; inside " << lit.name << ": " << c.triangles << " triangles, opaque, --surface-mode "
            << scene.surface_mode << "\n";
  const frame::FrameSettings& volume = choice.settings;
  const mixed::MixedPlan plan = mixed::plan_mixed_frame(lit, *surface::find_surface_mode(scene.surface_mode),
                                                        scene.shadows.value_or(scene.default_shadows), choice.mesh, volume);
  std::cout << "plan (first frame, on a device that traces rays):\n  1. the surfaces (their depth read back along the viewing axis: "
               "where the volume's rays end):\n";
  print_plan(plan.surfaces, "    ");
  std::cout << "  2. the volume, each ray ending at the surfaces' depth (backend " << frame::interval_backend_name(volume.backend)
            << (choice.backend_auto ? ", or as auto chooses on the device" : "") << "):\n";
  print_plan(plan.volume, "    ");
  std::cout << "  3. " << mixed::kCompositePass << " (CPU): " << plan.composite << "\n";
  return kOk;
}

}  // namespace

int info_plan(const ParsedArgs& a) {
  if (files_mix_kinds(a.files)) return mixed_plan(a);
  const surface::SurfaceMode* surface = a.has("mode") ? surface::find_surface_mode(a.values.at("mode")) : nullptr;
  if (!a.has("mode") && a.files.size() == 1 && is_named_surface_scene(a.files.front())) surface = &surface::surface_mode_table().front();
  if (surface) return surface_plan(a, *surface);
  VolumeChoice choice = volume_choice(a);
  // What render would refuse, refused here too: the size, the camera, the depth limit.
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{800, 600};
  validate(camera_from(a, bounds_of(choice.mesh)));
  if (a.has("depth-limit")) choice.settings.resolve.depth_limit = read_depth_limit(a.values.at("depth-limit"), size);
  std::cout << choice.mesh.name << ": " << choice.mesh.tets.size() << " cells, mode " << choice.mode->name << ", quantity "
            << quantity_name(choice.quantity) << "\n";
  if (!choice.mode->gpu()) {
    std::cout << "plan: the CPU double-precision reference, one pass on the CPU (no GPU passes)\n";
    return kOk;
  }
  if (choice.backend_auto) {  // measured on the device that would draw it (the default one)
    vk::Instance instance(vk::InstanceOptions{});
    const auto devices = vk::query_devices(instance.get());
    vk::Device device(instance, vk::select_device(devices, std::nullopt), {});
    resolve_auto_backend(choice.settings, device);
  }
  std::cout << "backend: " << frame::interval_backend_name(choice.settings.backend)
            << (choice.settings.backend_reason.empty() ? " (asked for)" : " (" + choice.settings.backend_reason + ")") << "\n";
  // A first frame: nothing from an earlier frame to reuse (a still camera later skips the ordering).
  frame::SceneContents scene;
  scene.volumes.push_back(frame::volume_contents(choice.mesh, choice.settings.resolve));
  const frame::FramePlan plan = frame::plan_frame(scene, choice.settings);
  std::cout << "plan (first frame):\n";
  for (const frame::PlannedPass& p : plan.passes)
    std::cout << "  " << p.name << " (" << (p.kind == frame::PassKind::Gpu ? "GPU" : "CPU") << "): " << p.reason << "\n";
  std::cout << "skipped:" << (plan.skipped.empty() ? " none\n" : "\n");
  for (const frame::SkippedPass& s : plan.skipped) std::cout << "  " << s.name << ": " << s.reason << "\n";
  return kOk;
}

}  // namespace prismoid::app
