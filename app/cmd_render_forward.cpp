// `prismoid render SCENE --mode forward`: a surface scene through the forward GPU backend
// (renderer/surface/forward/forward_pass.hpp), linear RGB to PFM (or display sRGB to PNG).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "app/bench/bench_cases.hpp"
#include "app/cli.hpp"
#include "app/cli_args.hpp"
#include "app/commands.hpp"
#include "app/output_files.hpp"
#include "app/surface_args.hpp"
#include "io/image_io.hpp"
#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

io::FloatImage rgb_image(const surface::ForwardImage& f) {
  io::FloatImage image;
  image.width = f.width;
  image.height = f.height;
  image.channels = 3;
  image.pixels = f.rgb();
  return image;
}

// The median of each pass's time over the frames.
std::vector<vk::PassTiming> median_passes(const std::vector<std::vector<vk::PassTiming>>& frames) {
  std::vector<vk::PassTiming> out = frames.front();
  for (size_t p = 0; p < out.size(); ++p) {
    std::vector<double> ms;
    for (const auto& f : frames) ms.push_back(f[p].gpu_ms);
    std::sort(ms.begin(), ms.end());
    const size_t n = ms.size();
    out[p].gpu_ms = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
  }
  return out;
}

}  // namespace

bool wants_forward(const std::vector<std::string>& args) {
  for (size_t i = 1; i + 1 < args.size(); ++i)
    if (args[i] == "--mode" && args[i + 1] == "forward") return true;
  return false;
}

int cmd_render_forward(const std::vector<std::string>& args) {
  const ParsedArgs a =
      parse(args, 1, with_surface_color(with_camera({"output", "size", "mode", "quantity", "supersample", "frames", "stats", "device", "shadows"})), {"validate"});
  if (!a.has("output")) throw InputError("render", "--output OUT.pfm|OUT.png is required");
  const std::string output = a.values.at("output");
  OutputFiles files;
  declare_render_files(files, a);
  if (a.has("quantity") && a.values.at("quantity") != "color")
    throw InputError("--quantity", "--mode forward renders linear colour: use --quantity color");
  const uint32_t k = a.has("supersample") ? parse_uint("supersample", a.values.at("supersample")) : 1;
  if (k == 0 || k > 16) throw InputError("--supersample", "must be between 1 and 16 samples per pixel side");
  const uint32_t frames = a.has("frames") ? parse_uint("frames", a.values.at("frames")) : 1;
  if (frames == 0 || frames > 10000) throw InputError("--frames", "must be between 1 and 10000");
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{256, 256};
  enum class Shadows { Auto, On, Off } shadows_asked = Shadows::Auto;
  if (a.has("shadows")) {
    const std::string& v = a.values.at("shadows");
    if (v == "on") shadows_asked = Shadows::On;
    else if (v == "off") shadows_asked = Shadows::Off;
    else throw InputError("--shadows", "'" + v + "' is not on or off");
  }
  const SurfaceScene scene = surface_scene_from(a, "forward");
  const Camera camera = surface_camera(a, scene.camera);
  const SurfaceScene lit = with_default_lighting(scene, camera);  // a file without lights is never black

  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});
  const surface::GpuSurfaceScene gpu = surface::upload(device, lit);
  // Shadows by default where the device traces rays and the scene has a light that casts them.
  const bool casts = gpu.point_light_count + gpu.directional_light_count + gpu.emitter_count > 0;
  if (shadows_asked == Shadows::On && !device.ray_tracing_enabled())
    throw vk::NoSuitableDevice(caps.name + " has no ray tracing (VK_KHR_ray_tracing_pipeline and VK_KHR_acceleration_structure): "
                               "--shadows on needs it; use --shadows off");
  const bool shadows = shadows_asked == Shadows::On || (shadows_asked == Shadows::Auto && device.ray_tracing_enabled() && casts);
  std::unique_ptr<surface::ForwardPass> pass;
  std::unique_ptr<surface::ShadowedForwardPass> shadowed;
  std::unique_ptr<rt::SceneAccel> accel;
  if (shadows) {
    shadowed = std::make_unique<surface::ShadowedForwardPass>(device);
    accel = std::make_unique<rt::SceneAccel>(device, lit);  // origin: the bounds centre, as gpu.origin
  } else {
    pass = std::make_unique<surface::ForwardPass>(device);
  }
  auto render = [&] {
    if (shadows)
      return k == 1 ? surface::render_forward_shadowed(device, *shadowed, gpu, *accel, camera, size)
                    : surface::render_forward_shadowed_supersampled(device, *shadowed, gpu, *accel, camera, size, k);
    return k == 1 ? surface::render_forward(device, *pass, gpu, camera, size) : surface::render_forward_supersampled(device, *pass, gpu, camera, size, k);
  };
  if (frames > 1)
    bench::warm_up([&] { return vk::total_gpu_ms(render().passes); }, bench::kTimedWarmUpSeconds);
  surface::ForwardImage image;
  std::vector<std::vector<vk::PassTiming>> timings;
  for (uint32_t i = 0; i < frames; ++i) {
    image = render();
    timings.push_back(image.passes);
  }
  image.passes = median_passes(timings);
  files.write(output, [&](const std::string& file) { io::write_image(file, rgb_image(image)); });

  size_t covered = 0;
  for (size_t i = 3; i < image.rgba.size(); i += 4) covered += image.rgba[i] == 1.0f;
  std::cout << "wrote " << output << " (" << size.width << "x" << size.height << ", " << scene.name << ", " << gpu.triangle_count
            << " triangles, " << gpu.emitter_count << " emissive" << (k > 1 ? ", " + std::to_string(k) + "x" + std::to_string(k) + " supersampled" : "")
            << ") on " << caps.name << "\n";
  const double total = print_pass_times(std::cout, image.passes);
  std::cout << "  total: " << json_number(total) << " ms GPU" << (frames > 1 ? " (median of " + std::to_string(frames) + " frames)" : "") << "\n";
  if (k == 1 && shadows) std::cout << "  covered: " << covered << " pixels, " << image.shading_invocations << " shading invocations\n";
  else if (k == 1) std::cout << "  covered: " << covered << " pixels" << (image.statistics ? ", " + std::to_string(image.fragment_invocations) + " shading invocations" : "") << "\n";
  if (lit.directional_lights.size() != scene.directional_lights.size()) std::cout << "  no lights in the scene: default headlight and sky\n";
  if (shadows)
    std::cout << "  direct light with ray-traced shadows (one shadow ray per point or directional light, " << PRISMOID_EMITTER_SHADOW_SAMPLES
              << " per emissive triangle)\n";
  else
    std::cout << "  direct light without shadows" << (device.ray_tracing_enabled() ? (casts ? " (--shadows off)" : " (no light casts shadows)") : " (the device has no ray tracing)") << "\n";

  if (a.has("stats")) {
    std::ostringstream js;
    js << ",\n  \"device\": \"" << json_escape(caps.name) << "\",\n  \"driver\": \"" << json_escape(caps.driver_info)
       << "\",\n  \"dataset\": \"" << json_escape(scene.name) << "\",\n  \"mode\": \"forward\",\n  \"quantity\": \"color\",\n  \"width\": "
       << size.width << ",\n  \"height\": " << size.height << ",\n  \"supersample\": " << k << ",\n  \"triangles\": " << gpu.triangle_count
       << ",\n  \"emitters\": " << gpu.emitter_count << ",\n  \"gpu_scene_bytes\": " << gpu.bytes << ",\n  \"covered_pixels\": " << covered
       << ",\n  \"default_lighting\": " << (lit.directional_lights.size() != scene.directional_lights.size() ? "true" : "false");
    js << ",\n  \"shadows\": " << (shadows ? "true" : "false");
    if (image.statistics) js << ",\n  \"fragments\": " << image.fragment_invocations;
    if (shadows) js << ",\n  \"shading_invocations\": " << image.shading_invocations;
    js << ",\n  \"frames\": " << frames;
    files.write(a.values.at("stats"), [&](const std::string& file) {
      write_stats_json(file, js.str(), image.passes, instance.validation_log().count());
    });
  }
  files.commit();
  return validation_exit(instance);
}

}  // namespace prismoid::app
