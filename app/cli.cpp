#include "app/cli.hpp"

#include <charconv>
#include <chrono>
#include <memory>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <glm/common.hpp>

#include "app/viewer.hpp"
#include "io/image_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

const char* kUsage =
    "Prismoid: interval-shaded tetrahedral volumes, object-space shaded surfaces, and what accuracy costs in time.\n"
    "\n"
    "usage: prismoid [VERB] [options]\n"
    "\n"
    "verbs:\n"
    "  view [FILE]        open the window (the default verb when a display is available)\n"
    "  render [FILE]      render an image headless (the default verb without a display)\n"
    "  devices            list Vulkan devices and the features each mode needs\n"
    "  convert [IN] OUT   write a tetrahedral mesh (or the default dataset) as .vtu\n"
    "  help [VERB]        this text, or a verb's options\n"
    "\n"
    "With no FILE the embedded default dataset is shown. `prismoid VERB --help` for options.\n"
    "Exit codes: 0 ok, 2 bad input, 3 no suitable Vulkan device, 4 validation messages (--validate), 1 other failure.\n";

const char* kRenderHelp =
    "usage: prismoid render [FILE] --output OUT.png|OUT.pfm [options]\n"
    "\n"
    "  --output PATH        image to write: .png (display colour, sRGB) or .pfm (the quantity, float32)\n"
    "  --stats PATH         write a JSON file with the device, the passes that ran and their GPU times\n"
    "  --mode MODE          interval (interval shading on the GPU) | reference (CPU, double precision, exact)\n"
    "  --quantity Q         optical-depth | transmittance (default transmittance)\n"
    "  --size WxH           image size in pixels (default 800x600)\n"
    "  --eye x,y,z --target x,y,z --up x,y,z --fovy DEG --near N\n"
    "                       camera (default: framing the data from +z, fovy 40)\n"
    "  --device N           use Vulkan device N (see `prismoid devices`)\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n"
    "\n"
    "  --array NAME         array giving the extinction (vectors by magnitude): a cell array is constant\n"
    "                       per cell, a point array linear in each cell; default sigma = 1\n"
    "  --density-scale S    multiplies the extinction (default 1)\n"
    "\n"
    "FILE: a tetrahedral .vtu or legacy .vtk unstructured grid. With no FILE the embedded\n"
    "default dataset is rendered.\n";

const char* kViewHelp =
    "usage: prismoid view [FILE] [options]\n"
    "\n"
    "  --size WxH           initial window size (default 1280x800)\n"
    "  --array NAME --density-scale S   extinction from a cell array, as for render\n"
    "  --eye/--target/--up/--fovy/--near   initial camera, as for render\n"
    "  --frames N           close after N frames (for scripted runs)\n"
    "  --device N           use Vulkan device N\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n"
    "\n"
    "Mouse: left drag orbits, wheel zooms. Keys: R resets the camera, Esc closes.\n";

const char* kDevicesHelp =
    "usage: prismoid devices [--validate]\n"
    "\n"
    "Lists every Vulkan device with its driver, the features Prismoid's modes use (yes/no), and\n"
    "which device `render` and `view` would choose.\n";

// --name value options and --flag options of a verb, in order of appearance.
struct ParsedArgs {
  std::vector<std::string> files;
  std::map<std::string, std::string> values;
  std::map<std::string, bool> flags;
  bool has(const std::string& k) const { return values.count(k) > 0; }
};

ParsedArgs parse(const std::vector<std::string>& args, size_t first, const std::vector<std::string>& value_options,
                 const std::vector<std::string>& flag_options) {
  ParsedArgs parsed;
  for (size_t i = first; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) == 0) {
      std::string name = a.substr(2), value;
      bool inline_value = false;
      if (auto eq = name.find('='); eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
        inline_value = true;
      }
      if (std::find(flag_options.begin(), flag_options.end(), name) != flag_options.end()) {
        parsed.flags[name] = true;
      } else if (std::find(value_options.begin(), value_options.end(), name) != value_options.end()) {
        if (!inline_value) {
          if (i + 1 >= args.size()) throw InputError("--" + name, "needs a value");
          value = args[++i];
        }
        parsed.values[name] = value;
      } else {
        throw InputError(a, "unknown option (see --help)");
      }
    } else {
      parsed.files.push_back(a);
    }
  }
  return parsed;
}

double parse_double(const std::string& option, const std::string& text) {
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v))
    throw InputError("--" + option, "'" + text + "' is not a finite number");
  return v;
}

uint32_t parse_uint(const std::string& option, const std::string& text) {
  uint32_t v = 0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) throw InputError("--" + option, "'" + text + "' is not a whole number");
  return v;
}

glm::dvec3 parse_vec3(const std::string& option, const std::string& text) {
  std::array<double, 3> v{};
  size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    size_t end = text.find(',', start);
    if ((i < 2) != (end != std::string::npos)) throw InputError("--" + option, "expects three numbers x,y,z, got '" + text + "'");
    v[i] = parse_double(option, text.substr(start, end == std::string::npos ? std::string::npos : end - start));
    start = end + 1;
  }
  return {v[0], v[1], v[2]};
}

VkExtent2D parse_size(const std::string& text) {
  const auto x = text.find('x');
  if (x == std::string::npos) throw InputError("--size", "expects WxH, e.g. 800x600, got '" + text + "'");
  const uint32_t w = parse_uint("size", text.substr(0, x)), h = parse_uint("size", text.substr(x + 1));
  if (w == 0 || h == 0 || w > 16384 || h > 16384) throw InputError("--size", "each side must be between 1 and 16384 pixels");
  return {w, h};
}

std::optional<uint32_t> parse_device(const ParsedArgs& a) {
  if (!a.has("device")) return std::nullopt;
  return parse_uint("device", a.values.at("device"));
}

// The dataset named on the command line; the embedded default when none is named.
TetMesh load_scene(const ParsedArgs& a) {
  io::TetReadOptions options;
  if (a.has("array")) options.array = a.values.at("array");
  if (a.has("density-scale")) {
    options.density_scale = parse_double("density-scale", a.values.at("density-scale"));
    if (options.density_scale < 0.0) throw InputError("--density-scale", "must not be negative");
  }
  if (a.files.empty()) {
    if (a.has("array")) throw InputError("--array", "the embedded default dataset has no arrays to choose from");
    TetMesh mesh = make_default_volume();
    for (double& s : mesh.cell_extinction) s *= options.density_scale;
    return mesh;
  }
  if (a.files.size() > 1) throw InputError(a.files[1], "several datasets in one scene arrive with the viewer; give one FILE");
  return io::read_tet_mesh(a.files.front(), options);
}

Camera camera_from(const ParsedArgs& a, const Bounds& bounds) {
  Camera c = fit_camera(bounds, a.has("fovy") ? parse_double("fovy", a.values.at("fovy")) : 40.0);
  if (a.has("eye")) c.eye = parse_vec3("eye", a.values.at("eye"));
  if (a.has("target")) c.target = parse_vec3("target", a.values.at("target"));
  if (a.has("up")) c.up = parse_vec3("up", a.values.at("up"));
  if (a.has("near")) c.near_distance = parse_double("near", a.values.at("near"));
  validate(c);
  return c;
}

const std::vector<std::string> kCameraOptions = {"eye", "target", "up", "fovy", "near"};

std::vector<std::string> with_camera(std::vector<std::string> v) {
  v.insert(v.end(), kCameraOptions.begin(), kCameraOptions.end());
  return v;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '"' || ch == '\\') { out += '\\'; out += ch; }
    else if (static_cast<unsigned char>(ch) < 0x20) { char buf[8]; std::snprintf(buf, sizeof buf, "\\u%04x", ch); out += buf; }
    else out += ch;
  }
  return out;
}

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

int validation_exit(const vk::Instance& instance) {
  const size_t n = instance.validation_log().count();
  if (n == 0) return kOk;
  std::cerr << "prismoid: the validation layer reported " << n << " message(s)\n";
  return kValidationMessages;
}

int cmd_devices(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, {}, {"validate", "help"});
  if (a.flags.count("help")) { std::cout << kDevicesHelp; return kOk; }
  vk::Instance instance({.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  auto yn = [](bool b) { return b ? "yes" : "no"; };
  if (devices.empty()) { std::cout << "no Vulkan devices found\n"; return kNoDevice; }
  for (const auto& d : devices) {
    std::cout << "device " << d.index << ": " << d.name << "\n"
              << "  type: " << d.type << ", Vulkan " << vk::version_string(d.api_version) << "\n"
              << "  driver: " << d.driver_name << " (" << d.driver_info << ")\n"
              << "  device-local memory: " << (d.device_local_bytes >> 20) << " MiB\n"
              << "  mesh shader: " << yn(d.mesh_shader) << " (task shader: " << yn(d.task_shader)
              << ", max outputs " << d.max_mesh_output_vertices << " vertices / " << d.max_mesh_output_primitives << " primitives)\n"
              << "  ray-tracing pipeline: " << yn(d.ray_tracing_pipeline) << "\n"
              << "  acceleration structures: " << yn(d.acceleration_structure) << "\n"
              << "  ray query: " << yn(d.ray_query) << "\n"
              << "  timestamps: " << yn(d.timestamps) << " (" << d.timestamp_period_ns << " ns/tick)\n"
              << "  presentation (swapchain): " << yn(d.swapchain) << "\n"
              << "  modes:\n";
    for (const auto& m : vk::mode_requirements()) {
      std::string missing;
      for (auto f : m.required)
        if (!vk::has_feature(d, f)) missing += std::string(missing.empty() ? "" : ", ") + vk::feature_name(f);
      std::cout << "    " << m.mode << ": " << (missing.empty() ? "yes" : "no (needs " + missing + ")") << "\n";
    }
  }
  try {
    const auto& chosen = vk::select_device(devices, std::nullopt);
    std::cout << "default choice: device " << chosen.index << " (" << chosen.name << ")\n";
  } catch (const vk::NoSuitableDevice& e) {
    std::cout << "default choice: none: " << e.what() << "\n";
  }
  return validation_exit(instance);
}

// The CPU double-precision reference, resolved the way the GPU's resolve pass does it.
frame::OffscreenFrame render_reference(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                       VkExtent2D size) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<double> tau = reference::optical_depth_image(mesh, camera, size.width, size.height);
  frame::OffscreenFrame f;
  f.width = size.width;
  f.height = size.height;
  f.quantity.resize(tau.size());
  f.display.resize(tau.size() * 4);
  for (size_t i = 0; i < tau.size(); ++i) {
    const double t = std::exp(-tau[i]);
    f.quantity[i] = float(resolve.quantity == volume::Quantity::Transmittance ? t : tau[i]);
    const glm::dvec3 c = glm::mix(glm::dvec3(resolve.medium), glm::dvec3(resolve.background), t);
    f.display[4 * i + 0] = float(c.r);
    f.display[4 * i + 1] = float(c.g);
    f.display[4 * i + 2] = float(c.b);
    f.display[4 * i + 3] = 1.0f;
  }
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  f.passes.push_back({"reference (CPU, double)", ms});
  return f;
}

int cmd_render(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, with_camera({"output", "stats", "mode", "quantity", "size", "device", "tf", "array", "density-scale"}), {"validate", "help"});
  if (a.flags.count("help")) { std::cout << kRenderHelp; return kOk; }
  if (!a.has("output")) throw InputError("render", "--output OUT.png|OUT.pfm is required");
  const std::string output = a.values.at("output");
  if (!io::is_supported_image_path(output)) throw InputError(output, "unknown image type: use .png or .pfm");
  const std::string mode = a.has("mode") ? a.values.at("mode") : "interval";
  if (mode != "interval" && mode != "reference")
    throw InputError("--mode", "unknown mode '" + mode + "' (available: interval, reference)");
  volume::Quantity quantity = volume::Quantity::Transmittance;
  if (a.has("quantity")) {
    const std::string& q = a.values.at("quantity");
    if (q == "optical-depth") quantity = volume::Quantity::OpticalDepth;
    else if (q == "transmittance") quantity = volume::Quantity::Transmittance;
    else if (q == "color") throw InputError("--quantity", "'color' needs transfer functions, which arrive with emission-absorption");
    else throw InputError("--quantity", "unknown quantity '" + q + "' (optical-depth, transmittance)");
  }
  if (a.has("tf")) throw InputError("--tf", "transfer functions arrive with emission-absorption rendering");
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{800, 600};
  const auto device_index = parse_device(a);

  const TetMesh mesh = load_scene(a);
  validate(mesh);
  const Camera camera = camera_from(a, bounds_of(mesh));

  frame::FrameSettings settings;
  settings.resolve.quantity = quantity;
  frame::OffscreenFrame result;
  std::string device_name, driver;
  std::unique_ptr<vk::Instance> instance;
  if (mode == "reference") {
    device_name = "CPU reference (double precision)";
    result = render_reference(mesh, camera, settings.resolve, size);
  } else {
    instance = std::make_unique<vk::Instance>(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
    const auto devices = vk::query_devices(instance->get());
    const auto& caps = vk::select_device(devices, device_index);
    device_name = caps.name;
    driver = caps.driver_info;
    vk::Device device(*instance, caps, {});
    frame::FrameRenderer renderer(device, mesh);
    result = renderer.render_offscreen(camera, settings, size);
  }
  const size_t validation_messages = instance ? instance->validation_log().count() : 0;

  io::FloatImage image;
  image.width = result.width;
  image.height = result.height;
  if (output.size() >= 4 && (output.substr(output.size() - 4) == ".pfm" || output.substr(output.size() - 4) == ".PFM")) {
    image.channels = 1;
    image.pixels = result.quantity;
  } else {
    image.channels = 4;
    image.pixels = result.display;
  }
  io::write_image(output, image);

  std::cout << "wrote " << output << " (" << size.width << "x" << size.height << ", " << mesh.name << ", "
            << mesh.tets.size() << " cells) on " << device_name << "\n";
  double total = 0.0;
  for (const auto& p : result.passes) {
    std::cout << "  " << p.name << ": " << (std::isfinite(p.gpu_ms) ? json_number(p.gpu_ms) + " ms" : "no timestamps")
              << (mode == "reference" ? " CPU" : " GPU") << "\n";
    total += p.gpu_ms;
  }
  std::cout << "  total: " << json_number(total) << (mode == "reference" ? " ms CPU\n" : " ms GPU\n");

  if (a.has("stats")) {
    const std::string stats_path = a.values.at("stats");
    std::ostringstream js;
    js << "{\n  \"device\": \"" << json_escape(device_name) << "\",\n  \"driver\": \"" << json_escape(driver)
       << "\",\n  \"dataset\": \"" << json_escape(mesh.name) << "\",\n  \"cells\": " << mesh.tets.size()
       << ",\n  \"mode\": \"" << mode << "\",\n  \"quantity\": \""
       << (quantity == volume::Quantity::OpticalDepth ? "optical-depth" : "transmittance") << "\",\n  \"width\": " << size.width
       << ",\n  \"height\": " << size.height << ",\n  \"passes\": [";
    for (size_t i = 0; i < result.passes.size(); ++i)
      js << (i ? ",\n" : "\n") << "    {\"name\": \"" << json_escape(result.passes[i].name)
         << "\", \"gpu_ms\": " << json_number(result.passes[i].gpu_ms) << "}";
    js << "\n  ],\n  \"gpu_ms_total\": " << json_number(total) << ",\n  \"validation_messages\": "
       << validation_messages << "\n}\n";
    std::ofstream out(stats_path);
    if (!out || !(out << js.str())) throw InputError(stats_path, "cannot write the stats file");
  }
  return instance ? validation_exit(*instance) : kOk;
}

const char* kConvertHelp =
    "usage: prismoid convert [IN] OUT.vtu [--array NAME --density-scale S]\n"
    "\n"
    "Writes a tetrahedral mesh as VTK XML (.vtu): the cell array 'extinction' and, where the\n"
    "input has one, the point array 'scalars'. IN is a .vtu/.vtk file; without IN, the embedded\n"
    "default dataset is written (its point array 'scalars' holds the field sampled at the points).\n";

int cmd_convert(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, {"array", "density-scale"}, {"help"});
  if (a.flags.count("help")) { std::cout << kConvertHelp; return kOk; }
  if (a.files.empty() || a.files.size() > 2) throw InputError("convert", "expects [IN] OUT.vtu (see --help)");
  const std::string out = a.files.back();
  if (std::filesystem::path(out).extension() != ".vtu") throw InputError(out, "convert writes .vtu files only (for now)");
  a.files.pop_back();
  TetMesh mesh = load_scene(a);
  if (mesh.point_scalars.empty() && mesh.linear_extinction()) mesh.point_scalars = mesh.point_extinction;
  io::write_tet_mesh_vtu(out, mesh);
  std::cout << "wrote " << out << " (" << mesh.tets.size() << " tetrahedra, " << mesh.points.size() << " points)\n";
  return kOk;
}

int cmd_view(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, with_camera({"size", "frames", "device", "array", "density-scale"}), {"validate", "help"});
  if (a.flags.count("help")) { std::cout << kViewHelp; return kOk; }
  const TetMesh mesh = load_scene(a);
  validate(mesh);
  ViewerOptions options;
  if (a.has("size")) {
    const VkExtent2D s = parse_size(a.values.at("size"));
    options.width = s.width;
    options.height = s.height;
  }
  options.validation = a.flags.count("validate") > 0;
  options.device_index = parse_device(a);
  if (a.has("frames")) options.max_frames = parse_uint("frames", a.values.at("frames"));
  bool any_camera = false;
  for (const auto& k : kCameraOptions) any_camera = any_camera || a.has(k);
  if (any_camera) options.camera = camera_from(a, bounds_of(mesh));
  if (!display_available()) throw InputError("view", "no display (DISPLAY is not set); use `prismoid render --output X.png`");
  const ViewerReport report = run_viewer(mesh, options);
  std::cout << "presented " << report.frames_presented << " frames on " << report.device_name << "\n";
  if (options.validation && report.validation_messages > 0) {
    std::cerr << "prismoid: the validation layer reported " << report.validation_messages << " message(s)\n";
    return kValidationMessages;
  }
  return kOk;
}

int dispatch(const std::vector<std::string>& args) {
  if (args.empty()) {
    if (display_available()) return cmd_view({"view"});
    std::cout << "no display: rendering the default dataset to prismoid-default.png\n";
    return cmd_render({"render", "--output", "prismoid-default.png"});
  }
  const std::string& verb = args.front();
  if (verb == "--help" || verb == "-h") { std::cout << kUsage; return kOk; }
  if (verb == "help") {
    if (args.size() > 1 && args[1] == "render") std::cout << kRenderHelp;
    else if (args.size() > 1 && args[1] == "view") std::cout << kViewHelp;
    else if (args.size() > 1 && args[1] == "devices") std::cout << kDevicesHelp;
    else if (args.size() > 1 && args[1] == "convert") std::cout << kConvertHelp;
    else std::cout << kUsage;
    return kOk;
  }
  if (verb == "devices") return cmd_devices(args);
  if (verb == "render") return cmd_render(args);
  if (verb == "view") return cmd_view(args);
  if (verb == "convert") return cmd_convert(args);
  if (verb.rfind("--", 0) == 0) {  // options without a verb: the default verb
    std::vector<std::string> with_verb{display_available() ? "view" : "render"};
    with_verb.insert(with_verb.end(), args.begin(), args.end());
    return with_verb.front() == "view" ? cmd_view(with_verb) : cmd_render(with_verb);
  }
  throw InputError(verb, "unknown verb (verbs: view, render, convert, devices, help)");
}

}  // namespace

int run_cli(const std::vector<std::string>& args) {
  try {
    return dispatch(args);
  } catch (const InputError& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kBadInput;
  } catch (const vk::NoSuitableDevice& e) {
    std::cerr << "prismoid: no suitable Vulkan device: " << e.what() << "\n";
    return kNoDevice;
  } catch (const std::exception& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kFailure;
  }
}

}  // namespace prismoid::app
