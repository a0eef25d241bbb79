#include "app/cli.hpp"

#include <algorithm>
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
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "app/dataset_report.hpp"
#include "app/terminal_progress.hpp"
#include "app/viewer.hpp"
#include "io/dataset_info.hpp"
#include "io/image_io.hpp"
#include "io/image_volume_io.hpp"
#include "io/surface_io.hpp"
#include "io/transfer_function_io.hpp"
#include "io/vtk_tet_io.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/analytic_march.hpp"
#include "renderer/reference/emission_absorption.hpp"
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
    "  info FILE          cells by type, points, arrays and their ranges, bounds, GPU memory, conversion\n"
    "  help [VERB]        this text, or a verb's options\n"
    "\n"
    "With no FILE the embedded default dataset is shown. `prismoid VERB --help` for options.\n"
    "Exit codes: 0 ok, 2 bad input, 3 no suitable Vulkan device, 4 validation messages (--validate), 130 cancelled\n"
    "(Ctrl-C during a long load), 1 other failure.\n";

const char* kRenderHelp =
    "usage: prismoid render [FILE] --output OUT.png|OUT.pfm [options]\n"
    "\n"
    "  --output PATH        image to write: .png (display colour, sRGB) or .pfm (the quantity, float32)\n"
    "  --stats PATH         write a JSON file with the device, the passes that ran and their GPU times\n"
    "  --mode MODE          interval               interval shading on the GPU, cells in mesh order\n"
    "                       interval-sorted        ... cells sorted by centroid distance on the GPU each frame\n"
    "                       interval-exact-order   ... cells in topological visibility order (exact on convex meshes)\n"
    "                       interval-march         marching inside intervals: each fragment samples the\n"
    "                                              analytic field of a field: dataset along its interval\n"
    "                                              (cells sorted on the GPU for color)\n"
    "                       interval-march-exact-order  ... cells in topological visibility order\n"
    "                       reference              CPU, double precision, exact per-pixel order (with a\n"
    "                                              field: dataset, of the analytic field itself)\n"
    "                       (default: interval; interval-sorted for --quantity color)\n"
    "  --quantity Q         optical-depth | transmittance | color | isosurface (default transmittance)\n"
    "                       color: emission-absorption of a scalar field through a transfer function\n"
    "                       isosurface: the nearest point where the field reaches --isovalue, shaded\n"
    "                       with a headlight (interval-march or reference, field: datasets); the\n"
    "                       .pfm quantity is the distance from the eye to it (0: no hit)\n"
    "  --size WxH           image size in pixels (default 800x600)\n"
    "  --eye x,y,z --target x,y,z --up x,y,z --fovy DEG --near N\n"
    "                       camera (default: framing the data from +z, fovy 40)\n"
    "  --device N           use Vulkan device N (see `prismoid devices`)\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n"
    "  --tetlet-size N      cells per mesh workgroup: 1 (the paper's one cell per workgroup), 4, 8 or 16\n"
    "                       (default 16)\n"
    "  --shared-vertices    tetlets: group neighbouring cells so a workgroup loads their shared points\n"
    "                       once (order-independent quantities, or --mode interval)\n"
    "  --frames N           render N timed frames after one warm-up frame; times are the median\n"
    "                       (stats also give min and max) (default 1, no warm-up)\n"
    "\n"
    "  --array NAME         array giving the extinction, or for color the transfer function's scalar\n"
    "                       (vectors by magnitude): a cell array is constant per cell, a point array\n"
    "                       linear in each cell; default sigma = 1 (the default dataset: its density)\n"
    "  --component C        of a vector --array: 0, 1, 2... or x, y, z (default: magnitude)\n"
    "  --density-scale S    multiplies the extinction; for color, the extinction at opacity 1 (default 1)\n"
    "\n"
    "  interval-march only:\n"
    "  --march-step S       longest step in world units: each interval is marched in equal steps of at\n"
    "                       most S (midpoint rule) (default: 1/100 of the bounds' diagonal)\n"
    "  --isovalue V         the isosurface's level (--quantity isosurface only; default 0.5)\n"
    "\n"
    "  color only:\n"
    "  --tf PRESET|FILE     transfer function: cool-to-warm (default), viridis, grayscale, black-body,\n"
    "                       or a ParaView colour-map JSON file (opacity from its \"Points\", else a ramp)\n"
    "  --tf-range LO,HI     scalar values mapped to the ends of the transfer function (default: data range)\n"
    "  --preintegration-size N   0: integrate each segment exactly in the shader (default); N in 2..256:\n"
    "                       look segments up in an N^3 pre-integrated table (faster, approximate)\n"
    "  --background R,G,B   linear colour behind the volume (default 1,1,1)\n"
    "\n"
    "FILE: an unstructured grid (.vtu, legacy .vtk, multiblock .vtm, parallel .pvtu; cells other than\n"
    "tetrahedra are split into conforming tetrahedra, with a note), or field:NAME[:N], an analytic field\n"
    "in world coordinates bounded by the box [-1,1]^3 split into N^3 cubes of 6 tetrahedra (default\n"
    "N = 4: each cell holds a strongly non-linear field). NAME: marschner-lobb (Marschner & Lobb 1994,\n"
    "f_M = 6, alpha = 0.25, values in [0,1]), blobs (three Gaussian blobs), sphere (one Gaussian blob:\n"
    "its isosurfaces are spheres), linear. The field is the extinction (times --density-scale) and\n"
    "the color scalar; interval modes render its linear interpolant at the mesh points,\n"
    "interval-march and reference the field itself. FILE may also be a closed triangle surface\n"
    "(.vtp .stl .obj .ply .off), filled with tetrahedra by TetGen (extinction 1 per cell):\n"
    "  --tetgen-quality Q       radius-edge bound, TetGen -q (default 1.414; smaller: rounder, more cells)\n"
    "  --tetgen-max-volume V    largest cell volume, TetGen -a (default: none)\n"
    "  --fill-holes             close an open surface first (VTK's vtkFillHolesFilter)\n"
    "or an image volume (.vti .mhd .mha, .inr/.inr.gz as in CGAL's data): each cell between 8 voxel\n"
    "centres becomes 6 tetrahedra, voxel values are point values (--array picks the .vti/.mhd array);\n"
    "  --subsample K            keep 1 voxel in K per axis (images over 50 million cells need it)\n"
    "ball[:S] is a unit ball of constant extinction (an icosphere subdivided S times, default 3, one\n"
    "tetrahedron per boundary triangle): its optical depth is sigma times the chord, in closed form.\n"
    "With no FILE the embedded default dataset is rendered.\n";

const char* kViewHelp =
    "usage: prismoid view [FILE] [options]\n"
    "\n"
    "  --size WxH           initial window size (default 1280x800)\n"
    "  --mode, --quantity, --array, --density-scale, --tf, --tf-range, --preintegration-size,\n"
    "  --background, --tetlet-size, --shared-vertices, --march-step, --isovalue\n"
    "                       what to show and how, as for render (not --mode reference)\n"
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

// The analytic field of a field:NAME[:N] dataset, if that is what the command line names.
std::optional<volume::AnalyticField> field_of(const ParsedArgs& a) {
  if (a.files.size() != 1 || a.files.front().rfind("field:", 0) != 0) return std::nullopt;
  const std::string spec = a.files.front().substr(6);
  return volume::field_from_name(spec.substr(0, spec.find(':')));
}

// The dataset named on the command line; the embedded default when none is named.
TetMesh load_scene(const ParsedArgs& a, bool scalar_field = false) {
  io::TetReadOptions options;
  if (a.has("array")) options.array = a.values.at("array");
  if (a.has("component")) {
    const std::string& c = a.values.at("component");
    if (!a.has("array")) throw InputError("--component", "picks a component of the --array NAME");
    options.component = c == "x" || c == "X" ? 0 : c == "y" || c == "Y" ? 1 : c == "z" || c == "Z" ? 2
                        : c == "magnitude" ? -1 : int(parse_uint("component", c));
  }
  if (scalar_field) options.role = io::ArrayRole::Scalars;
  if (a.has("density-scale")) {
    options.density_scale = parse_double("density-scale", a.values.at("density-scale"));
    if (options.density_scale < 0.0) throw InputError("--density-scale", "must not be negative");
  }
  const bool is_image = !a.files.empty() && io::is_image_volume_path(a.files.front());
  if (a.has("subsample") && !is_image) throw InputError("--subsample", "applies to image volumes (.vti .mhd .mha .inr) only");
  const bool is_surface = !a.files.empty() && io::is_surface_path(a.files.front());
  for (const char* option : {"tetgen-quality", "tetgen-max-volume"})
    if (a.has(option) && !is_surface) throw InputError(std::string("--") + option, "applies to surfaces (.vtp .stl .obj .ply .off) only");
  if (a.flags.count("fill-holes") && !is_surface) throw InputError("--fill-holes", "applies to surfaces (.vtp .stl .obj .ply .off) only");
  if (a.files.empty()) {
    if (a.has("array")) throw InputError("--array", "the embedded default dataset has no arrays to choose from");
    TetMesh mesh = make_default_volume();
    if (!scalar_field)
      for (double& s : mesh.cell_extinction) s *= options.density_scale;
    return mesh;
  }
  if (a.files.size() > 1) throw InputError(a.files[1], "several datasets in one scene arrive with the viewer; give one FILE");
  if (const auto field = field_of(a)) {
    if (a.has("array")) throw InputError("--array", "a field: dataset has no arrays to choose from");
    const std::string& spec = a.files.front();
    uint32_t n = 4;
    if (const auto colon = spec.find(':', 6); colon != std::string::npos) {
      n = parse_uint("field", spec.substr(colon + 1));
      if (n == 0 || n > 128) throw InputError(spec, "the box is split into N^3 cubes with N between 1 and 128 (12.6 million cells)");
    }
    return volume::make_field_mesh(*field, n, options.density_scale);
  }
  const std::string& file = a.files.front();
  if (file.rfind("ball", 0) == 0 && (file.size() == 4 || file[4] == ':')) {  // ball[:S]: the closed-form test volume
    uint32_t subdivisions = 3;
    if (file.size() > 4) {
      subdivisions = parse_uint("ball", file.substr(5));
      if (subdivisions > 7) throw InputError(file, "subdivisions go from 0 (an icosahedron, 20 cells) to 7 (327,680 cells)");
    }
    if (a.has("array")) throw InputError("--array", "the ball has no arrays to choose from");
    return make_ball_mesh(glm::dvec3(0.0), 1.0, subdivisions, options.density_scale);
  }
  if (io::is_surface_path(file)) {  // a closed surface, filled with tetrahedra by TetGen
    if (a.has("array")) throw InputError("--array", file + " is a surface: its tetrahedra carry no arrays");
    io::SurfaceToTets convert;
    convert.fill_holes = a.flags.count("fill-holes") > 0;
    if (a.has("tetgen-quality")) convert.tetgen.radius_edge_ratio = parse_double("tetgen-quality", a.values.at("tetgen-quality"));
    if (a.has("tetgen-max-volume")) convert.tetgen.max_volume = parse_double("tetgen-max-volume", a.values.at("tetgen-max-volume"));
    const auto start = std::chrono::steady_clock::now();
    TerminalProgress progress(file);
    convert.progress = progress.callback();
    io::SurfaceTets tets = io::surface_to_tets(file, convert);
    progress.throw_if_cancelled(file);
    TetMesh mesh = std::move(tets.mesh);
    for (double& s : mesh.cell_extinction) s *= options.density_scale;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (tets.from_cache)
      std::cerr << "prismoid: " << file << ": " << mesh.tets.size() << " tetrahedra from the cache (" << tets.cache_file << ") in "
                << seconds << " s\n";
    else
      std::cerr << "prismoid: " << file << ": " << tets.triangles << " triangles -> " << mesh.tets.size()
                << " tetrahedra by TetGen in " << seconds << " s\n";
    return mesh;
  }
  if (a.has("component") && (io::is_image_volume_path(file) || io::is_surface_path(file)))
    throw InputError("--component", "applies to the arrays of .vtu .vtk .vtm .pvtu meshes");
  if (io::is_image_volume_path(file)) {  // voxels: each cell between 8 voxel centres becomes 6 tetrahedra
    io::ImageReadOptions image;
    image.array = options.array;
    image.role = options.role;
    image.density_scale = options.density_scale;
    if (a.has("subsample")) {
      image.subsample = parse_uint("subsample", a.values.at("subsample"));
      if (image.subsample == 0) throw InputError("--subsample", "must be at least 1");
    }
    image.max_cells = 50'000'000;  // about 1.2 GB on the GPU: larger needs --subsample
    TerminalProgress progress(file);
    image.progress = progress.callback();
    TetMesh mesh = io::read_image_volume(file, image);
    progress.throw_if_cancelled(file);
    return mesh;
  }
  io::MeshConversion conversion;
  TetMesh mesh = io::read_tet_mesh(file, options, &conversion);
  if (const std::string note = io::conversion_note(conversion); !note.empty())
    std::cerr << "prismoid: note: " << file << ": " << note << "\n";
  return mesh;
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

// A frame of `size` for a CPU reference to fill: one quantity and one RGBA display value per pixel.
frame::OffscreenFrame blank_frame(VkExtent2D size) {
  frame::OffscreenFrame f;
  f.width = size.width;
  f.height = size.height;
  f.quantity.resize(size_t(size.width) * size.height);
  f.display.resize(f.quantity.size() * 4);
  return f;
}

// The CPU double-precision reference, resolved the way the GPU's resolve pass does it.
frame::OffscreenFrame render_reference(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                       VkExtent2D size) {
  const auto start = std::chrono::steady_clock::now();
  frame::OffscreenFrame f = blank_frame(size);
  const size_t pixels = f.quantity.size();
  if (resolve.quantity == volume::Quantity::Color) {
    const auto image = reference::emission_absorption_image(mesh, resolve.transfer, camera, size.width, size.height);
    f.emission.resize(pixels * 4);
    for (size_t i = 0; i < pixels; ++i) {
      const glm::dvec4 c = image.pixels[i];
      const double transmittance = 1.0 - c.a;
      f.quantity[i] = float(transmittance);
      const glm::dvec3 shown = glm::dvec3(c) + transmittance * glm::dvec3(resolve.background);
      for (int k = 0; k < 3; ++k) f.display[4 * i + k] = float(shown[k]);
      f.display[4 * i + 3] = 1.0f;
      for (int k = 0; k < 4; ++k) f.emission[4 * i + k] = float(c[k]);
    }
    f.report.ordering = "exact (per pixel, CPU)";
  } else {
    const std::vector<double> tau = reference::optical_depth_image(mesh, camera, size.width, size.height);
    for (size_t i = 0; i < pixels; ++i) {
      const double t = std::exp(-tau[i]);
      f.quantity[i] = float(resolve.quantity == volume::Quantity::Transmittance ? t : tau[i]);
      const glm::dvec3 c = glm::mix(glm::dvec3(resolve.medium), glm::dvec3(resolve.background), t);
      for (int k = 0; k < 3; ++k) f.display[4 * i + k] = float(c[k]);
      f.display[4 * i + 3] = 1.0f;
    }
    f.report.ordering = "none (order-independent)";
  }
  f.report.order_exact = true;
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  f.passes.push_back({"reference (CPU, double)", ms});
  return f;
}

// The CPU reference of an analytic field (what interval-march approximates): optical depth by
// fine Gauss-Legendre panels, colour and isosurfaces by marching
// in steps of 1/2000 of the bounds' diagonal, resolved as the GPU does.
frame::OffscreenFrame render_field_reference(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                             VkExtent2D size) {
  const auto start = std::chrono::steady_clock::now();
  const volume::MarchSettings& m = resolve.march;
  const Bounds b = bounds_of(mesh);
  const double fine_step = glm::length(b.max - b.min) / 2000.0;
  frame::OffscreenFrame f = blank_frame(size);
  const size_t pixels = f.quantity.size();
  auto put = [&](size_t i, const glm::dvec3& c) {
    for (int k = 0; k < 3; ++k) f.display[4 * i + k] = float(c[k]);
    f.display[4 * i + 3] = 1.0f;
  };
  if (resolve.quantity == volume::Quantity::Color) {
    const auto image = reference::field_color_image(mesh, m.field, resolve.transfer, camera, size.width, size.height, fine_step);
    f.emission.resize(pixels * 4);
    for (size_t i = 0; i < pixels; ++i) {
      const glm::dvec4 c = image.pixels[i];
      f.quantity[i] = float(1.0 - c.a);
      put(i, glm::dvec3(c) + (1.0 - c.a) * glm::dvec3(resolve.background));
      for (int k = 0; k < 4; ++k) f.emission[4 * i + k] = float(c[k]);
    }
  } else if (resolve.quantity == volume::Quantity::Isosurface) {
    const auto image = reference::isosurface_image(mesh, m.field, m.isovalue, camera, size.width, size.height, fine_step);
    f.emission.resize(pixels * 4);
    for (size_t i = 0; i < pixels; ++i) {
      f.quantity[i] = float(image.distance[i]);
      put(i, image.distance[i] > 0.0 ? glm::dvec3(image.shade[i]) : glm::dvec3(resolve.background));
      for (int k = 0; k < 3; ++k) f.emission[4 * i + k] = float(image.shade[i]);
      f.emission[4 * i + 3] = float(image.distance[i]);
    }
  } else {
    const auto tau = reference::field_optical_depth_image(mesh, m.field, m.density_scale, camera, size.width, size.height);
    for (size_t i = 0; i < pixels; ++i) {
      const double t = std::exp(-tau[i]);
      f.quantity[i] = float(resolve.quantity == volume::Quantity::Transmittance ? t : tau[i]);
      put(i, glm::mix(glm::dvec3(resolve.medium), glm::dvec3(resolve.background), t));
    }
  }
  f.report.ordering = "exact (per pixel, CPU)";
  f.report.order_exact = true;
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  f.passes.push_back({"reference (CPU, double, analytic field)", ms});
  return f;
}

// Per pass, the median over the frames goes into `passes` (by name, in order); returns each
// pass's min and max.
std::vector<std::pair<double, double>> summarize_frames(const std::vector<std::vector<vk::PassTiming>>& frames,
                                                        std::vector<vk::PassTiming>& passes) {
  std::vector<std::pair<double, double>> spread;
  for (auto& pass : passes) {
    std::vector<double> ms;
    for (const auto& f : frames)
      for (const auto& p : f)
        if (p.name == pass.name) ms.push_back(p.gpu_ms);
    std::sort(ms.begin(), ms.end());
    if (ms.empty()) { spread.emplace_back(pass.gpu_ms, pass.gpu_ms); continue; }
    const size_t n = ms.size();
    pass.gpu_ms = n % 2 ? ms[n / 2] : 0.5 * (ms[n / 2 - 1] + ms[n / 2]);
    spread.emplace_back(ms.front(), ms.back());
  }
  return spread;
}

const char* quantity_name(volume::Quantity q) {
  switch (q) {
    case volume::Quantity::OpticalDepth: return "optical-depth";
    case volume::Quantity::Transmittance: return "transmittance";
    case volume::Quantity::Color: return "color";
    case volume::Quantity::Isosurface: return "isosurface";
  }
  return "?";
}

// The transfer function the color options describe, over the data's scalar range unless given.
volume::TransferFunction transfer_from(const ParsedArgs& a, const TetMesh& mesh) {
  volume::TransferFunction tf = io::transfer_function_from(a.has("tf") ? a.values.at("tf") : "cool-to-warm");
  const auto& field = mesh.point_scalars.empty() ? mesh.cell_scalars : mesh.point_scalars;
  if (field.empty())
    throw InputError(mesh.name, "has no scalar field for --quantity color (choose a point or cell array with --array NAME)");
  if (a.has("tf-range")) {
    const std::string& text = a.values.at("tf-range");
    const auto comma = text.find(',');
    if (comma == std::string::npos) throw InputError("--tf-range", "expects LO,HI, got '" + text + "'");
    tf.range_lo = parse_double("tf-range", text.substr(0, comma));
    tf.range_hi = parse_double("tf-range", text.substr(comma + 1));
    if (!(tf.range_hi > tf.range_lo)) throw InputError("--tf-range", "HI must be greater than LO");
  } else {
    const auto [lo, hi] = std::minmax_element(field.begin(), field.end());
    tf.range_lo = *lo;
    tf.range_hi = *hi > *lo ? *hi : *lo + 1.0;  // a constant field still maps somewhere
  }
  tf.density_scale = a.has("density-scale") ? parse_double("density-scale", a.values.at("density-scale")) : 1.0;
  const std::string name = tf.name;
  tf.name = "--tf " + name;
  volume::validate(tf);
  tf.name = name;
  return tf;
}

// The options render and view share: the data, what to show and how.
const std::vector<std::string> kVolumeOptions = {"mode", "quantity", "tf", "tf-range", "preintegration-size", "background",
                                                 "array", "density-scale", "tetlet-size", "march-step", "isovalue",
                                                 "tetgen-quality", "tetgen-max-volume", "subsample", "component"};

struct VolumeChoice {
  TetMesh mesh;
  std::string mode;
  volume::Quantity quantity = volume::Quantity::Transmittance;
  frame::FrameSettings settings;
};

// Parses the volume options, loads the data and builds the frame settings; InputError names
// the option or file at fault.
VolumeChoice volume_choice(const ParsedArgs& a) {
  VolumeChoice v;
  volume::Quantity& quantity = v.quantity;
  if (a.has("quantity")) {
    const std::string& q = a.values.at("quantity");
    if (q == "optical-depth") quantity = volume::Quantity::OpticalDepth;
    else if (q == "transmittance") quantity = volume::Quantity::Transmittance;
    else if (q == "color") quantity = volume::Quantity::Color;
    else if (q == "isosurface") quantity = volume::Quantity::Isosurface;
    else throw InputError("--quantity", "unknown quantity '" + q + "' (optical-depth, transmittance, color, isosurface)");
  }
  const bool color = quantity == volume::Quantity::Color;
  v.mode = a.has("mode") ? a.values.at("mode") : (color ? "interval-sorted" : "interval");
  const std::string& mode = v.mode;
  frame::FrameSettings& settings = v.settings;
  if (mode == "interval") settings.ordering = frame::Ordering::MeshOrder;
  else if (mode == "interval-sorted") settings.ordering = frame::Ordering::GpuSort;
  else if (mode == "interval-exact-order") settings.ordering = frame::Ordering::Exact;
  else if (mode == "interval-march") settings.ordering = frame::Ordering::GpuSort;
  else if (mode == "interval-march-exact-order") settings.ordering = frame::Ordering::Exact;
  else if (mode != "reference")
    throw InputError("--mode", "unknown mode '" + mode +
                                   "' (available: interval, interval-sorted, interval-exact-order, interval-march, "
                                   "interval-march-exact-order, reference)");
  const bool march = mode.rfind("interval-march", 0) == 0;
  const std::optional<volume::AnalyticField> field = field_of(a);
  if (march && !field) throw InputError("--mode " + mode, "marches an analytic field: give a field:NAME dataset (see --help)");
  if (quantity == volume::Quantity::Isosurface && !(field && (march || mode == "reference")))
    throw InputError("--quantity isosurface", "needs a field:NAME dataset and --mode interval-march or reference");
  if (a.has("isovalue") && quantity != volume::Quantity::Isosurface) throw InputError("--isovalue", "applies to --quantity isosurface only");
  if (a.has("march-step") && !march && mode != "reference")
    throw InputError("--march-step", "applies to --mode interval-march and interval-march-exact-order only");
  if (march && a.has("preintegration-size")) throw InputError("--preintegration-size", "does not apply to interval-march");
  if (!color)
    for (const char* option : {"tf", "tf-range", "preintegration-size", "background"})
      if (a.has(option)) throw InputError(std::string("--") + option, "applies to --quantity color only");
  v.mesh = load_scene(a, color);
  const TetMesh& mesh = v.mesh;
  validate(mesh);
  if (field) {
    volume::MarchSettings& m = settings.resolve.march;
    m.enabled = march;
    m.field = *field;
    const Bounds b = bounds_of(mesh);
    m.step = a.has("march-step") ? parse_double("march-step", a.values.at("march-step")) : glm::length(b.max - b.min) / 100.0;
    if (!(m.step > 0.0)) throw InputError("--march-step", "must be a positive number of world units");
    m.isovalue = a.has("isovalue") ? parse_double("isovalue", a.values.at("isovalue")) : 0.5;
    m.density_scale = a.has("density-scale") ? parse_double("density-scale", a.values.at("density-scale")) : 1.0;
  }

  settings.resolve.quantity = quantity;
  if (a.has("tetlet-size")) settings.resolve.tetlet_size = parse_uint("tetlet-size", a.values.at("tetlet-size"));
  settings.resolve.shared_vertices = a.flags.count("shared-vertices") > 0;
  if (color) {
    settings.resolve.transfer = transfer_from(a, mesh);
    if (a.has("preintegration-size")) settings.resolve.preintegration_size = parse_uint("preintegration-size", a.values.at("preintegration-size"));
    if (a.has("background")) {
      const glm::dvec3 bg = parse_vec3("background", a.values.at("background"));
      if (glm::any(glm::lessThan(bg, glm::dvec3(0.0))) || glm::any(glm::greaterThan(bg, glm::dvec3(1.0))))
        throw InputError("--background", "components must lie in [0, 1]");
      settings.resolve.background = glm::vec3(bg);
    }
    if (mode == "interval")
      std::cerr << "prismoid: note: color is order dependent and --mode interval draws cells in mesh order (approximate); "
                   "interval-sorted or interval-exact-order composite in depth order\n";
  }
  return v;
}

int cmd_render(const std::vector<std::string>& args) {
  std::vector<std::string> value_options = with_camera({"output", "stats", "size", "device", "frames"});
  value_options.insert(value_options.end(), kVolumeOptions.begin(), kVolumeOptions.end());
  ParsedArgs a = parse(args, 1, value_options, {"validate", "help", "shared-vertices", "fill-holes"});
  if (a.flags.count("help")) { std::cout << kRenderHelp; return kOk; }
  if (!a.has("output")) throw InputError("render", "--output OUT.png|OUT.pfm is required");
  const std::string output = a.values.at("output");
  if (!io::is_supported_image_path(output)) throw InputError(output, "unknown image type: use .png or .pfm");
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{800, 600};
  const auto device_index = parse_device(a);
  const uint32_t frames = a.has("frames") ? parse_uint("frames", a.values.at("frames")) : 1;
  if (frames == 0 || frames > 10000) throw InputError("--frames", "must be between 1 and 10000");
  const VolumeChoice choice = volume_choice(a);
  const TetMesh& mesh = choice.mesh;
  const std::string& mode = choice.mode;
  const volume::Quantity quantity = choice.quantity;
  const bool color = quantity == volume::Quantity::Color;
  const frame::FrameSettings& settings = choice.settings;
  const bool field = field_of(a).has_value();  // an analytic field: its own CPU reference
  const Camera camera = camera_from(a, bounds_of(mesh));
  frame::OffscreenFrame result;
  std::vector<std::pair<double, double>> pass_spread;  // min, max per pass over the timed frames
  std::string device_name, driver;
  std::unique_ptr<vk::Instance> instance;
  if (mode == "reference") {
    device_name = "CPU reference (double precision)";
    result = field ? render_field_reference(mesh, camera, settings.resolve, size) : render_reference(mesh, camera, settings.resolve, size);
  } else {
    instance = std::make_unique<vk::Instance>(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
    const auto devices = vk::query_devices(instance->get());
    const auto& caps = vk::select_device(devices, device_index);
    device_name = caps.name;
    driver = caps.driver_info;
    vk::Device device(*instance, caps, {});
    frame::FrameRenderer renderer(device, mesh);
    if (frames > 1) renderer.render_offscreen(camera, settings, size);  // warm-up: caches, clocks, first-use work
    std::vector<std::vector<vk::PassTiming>> timings;
    for (uint32_t i = 0; i < frames; ++i) {
      result = renderer.render_offscreen(camera, settings, size);
      timings.push_back(result.passes);
    }
    pass_spread = summarize_frames(timings, result.passes);
  }
  const size_t validation_messages = instance ? instance->validation_log().count() : 0;

  io::FloatImage image;
  image.width = result.width;
  image.height = result.height;
  const bool pfm = std::filesystem::path(output).extension() == ".pfm" || std::filesystem::path(output).extension() == ".PFM";
  if (pfm && !color) {  // isosurface: the distance to the hit
    image.channels = 1;
    image.pixels = result.quantity;
  } else if (pfm) {  // colour PFM: the linear colour over the background, RGB
    image.channels = 3;
    image.pixels.resize(result.display.size() / 4 * 3);
    for (size_t i = 0; i < result.display.size() / 4; ++i)
      for (int k = 0; k < 3; ++k) image.pixels[3 * i + k] = result.display[4 * i + k];
  } else {
    image.channels = 4;
    image.pixels = result.display;
  }
  io::write_image(output, image);

  const bool cpu = mode == "reference";
  std::cout << "wrote " << output << " (" << size.width << "x" << size.height << ", " << mesh.name << ", "
            << mesh.tets.size() << " cells) on " << device_name << "\n";
  std::cout << "  ordering: " << result.report.ordering << (result.report.order_exact ? " [exact]" : " [approximate]") << "\n";
  double total = 0.0;
  for (const auto& p : result.passes) {
    std::cout << "  " << p.name << ": " << (std::isfinite(p.gpu_ms) ? json_number(p.gpu_ms) + " ms" : "no timestamps")
              << (cpu ? " CPU" : " GPU") << "\n";
    total += p.gpu_ms;
  }
  std::cout << "  total: " << json_number(total) << (cpu ? " ms CPU\n" : " ms GPU\n");
  for (const auto& p : result.report.cpu_passes) std::cout << "  " << p.name << ": " << json_number(p.gpu_ms) << " ms CPU\n";
  if (result.report.counted) {
    std::cout << "  drawn: " << result.report.fragments << " fragments";
    if (result.report.primitives > 0) std::cout << ", " << result.report.primitives << " proxy triangles";
    std::cout << "\n";
  }

  if (a.has("stats")) {
    const std::string stats_path = a.values.at("stats");
    std::ostringstream js;
    js << "{\n  \"device\": \"" << json_escape(device_name) << "\",\n  \"driver\": \"" << json_escape(driver)
       << "\",\n  \"dataset\": \"" << json_escape(mesh.name) << "\",\n  \"cells\": " << mesh.tets.size()
       << ",\n  \"mode\": \"" << mode << "\",\n  \"quantity\": \"" << quantity_name(quantity) << "\",\n  \"width\": " << size.width
       << ",\n  \"height\": " << size.height << ",\n  \"ordering\": \"" << json_escape(result.report.ordering)
       << "\",\n  \"order_exact\": " << (result.report.order_exact ? "true" : "false")
       << ",\n  \"gpu_mesh_bytes\": " << result.report.mesh_bytes;
    if (result.report.counted) {  // as the driver counts them (lavapipe counts no clipper input for mesh shaders)
      js << ",\n  \"fragments\": " << result.report.fragments;
      if (result.report.primitives > 0) js << ",\n  \"proxy_triangles\": " << result.report.primitives;
    }
    js << ",\n  \"tetlet_size\": " << settings.resolve.tetlet_size << ",\n  \"shared_vertices\": "
       << (settings.resolve.shared_vertices ? "true" : "false");
    if (result.report.tetlet_points_per_cell > 0.0)
      js << ",\n  \"tetlet_points_per_cell\": " << json_number(result.report.tetlet_points_per_cell);
    if (color)
      js << ",\n  \"transfer_function\": \"" << json_escape(settings.resolve.transfer.name) << "\",\n  \"tf_range\": ["
         << json_number(settings.resolve.transfer.range_lo) << ", " << json_number(settings.resolve.transfer.range_hi)
         << "],\n  \"preintegration_size\": " << settings.resolve.preintegration_size;
    if (field)
      js << ",\n  \"field\": \"" << json_escape(settings.resolve.march.field.name) << "\",\n  \"march_step\": " << json_number(settings.resolve.march.step)
         << (quantity == volume::Quantity::Isosurface ? ",\n  \"isovalue\": " + json_number(settings.resolve.march.isovalue) : "");
    js << ",\n  \"frames\": " << frames << ",\n  \"passes\": [";
    for (size_t i = 0; i < result.passes.size(); ++i) {
      js << (i ? ",\n" : "\n") << "    {\"name\": \"" << json_escape(result.passes[i].name)
         << "\", \"gpu_ms\": " << json_number(result.passes[i].gpu_ms);
      if (i < pass_spread.size())
        js << ", \"min_ms\": " << json_number(pass_spread[i].first) << ", \"max_ms\": " << json_number(pass_spread[i].second);
      js << "}";
    }
    js << "\n  ],\n  \"cpu_passes\": [";
    for (size_t i = 0; i < result.report.cpu_passes.size(); ++i)
      js << (i ? ",\n" : "\n") << "    {\"name\": \"" << json_escape(result.report.cpu_passes[i].name)
         << "\", \"cpu_ms\": " << json_number(result.report.cpu_passes[i].gpu_ms) << "}";
    js << "\n  ],\n  \"gpu_ms_total\": " << json_number(total) << ",\n  \"validation_messages\": "
       << validation_messages << "\n}\n";
    std::ofstream out(stats_path);
    if (!out || !(out << js.str())) throw InputError(stats_path, "cannot write the stats file");
  }
  return instance ? validation_exit(*instance) : kOk;
}

const char* kConvertHelp =
    "usage: prismoid convert [IN] OUT.vtu [--array NAME --density-scale S]\n"
    "                        [--tetgen-quality Q --tetgen-max-volume V --fill-holes]\n"
    "\n"
    "Writes a tetrahedral mesh as VTK XML (.vtu): the cell array 'extinction' and, where the\n"
    "input has one, the point array 'scalars'. IN is a .vtu/.vtk/.vtm/.pvtu file (other cells are\n"
    "split into tetrahedra, pieces merged: see `prismoid info IN`), an image volume (.vti .mhd .mha\n"
    ".inr), a field:NAME[:N] dataset, or a closed surface (.vtp .stl .obj .ply .off) tetrahedralized\n"
    "by TetGen (see `render --help`); without IN, the embedded default dataset is written (its point\n"
    "array 'scalars' holds the field sampled at the points).\n";

int cmd_convert(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, {"array", "density-scale", "tetgen-quality", "tetgen-max-volume", "subsample"}, {"help", "fill-holes"});
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

const char* kInfoHelp =
    "usage: prismoid info FILE\n"
    "\n"
    "Describes a mesh file (.vtu, .vtk, .vtm, .pvtu) without rendering: its cells by type, points,\n"
    "point and cell arrays with their ranges (vectors by magnitude), bounds, and what reading it\n"
    "produces: the tetrahedra that other cells split into, zero-volume and inverted tetrahedra,\n"
    "and the GPU memory of the mesh buffers. An image volume (.vti .mhd .mha .inr): its voxels, value\n"
    "range, bounds and the tetrahedra it becomes. A surface (.vtp .stl .obj .ply .off): its triangles,\n"
    "bounds, and whether it is closed (where it is not), which TetGen needs.\n";

int cmd_info(const std::vector<std::string>& args) {
  ParsedArgs a = parse(args, 1, {}, {"help"});
  if (a.flags.count("help")) { std::cout << kInfoHelp; return kOk; }
  if (a.files.size() != 1) throw InputError("info", "expects one FILE (see --help)");
  const std::string& file = a.files.front();
  auto print_bounds = [](const Bounds& b) {
    std::cout << "  bounds: [" << b.min.x << ", " << b.max.x << "] x [" << b.min.y << ", " << b.max.y << "] x [" << b.min.z
              << ", " << b.max.z << "]\n";
  };
  if (io::is_image_volume_path(file)) {
    io::ImageReadOptions options;
    options.role = io::ArrayRole::Scalars;
    options.max_cells = 50'000'000;
    const TetMesh mesh = io::read_image_volume(file, options);
    const auto [lo, hi] = std::minmax_element(mesh.point_scalars.begin(), mesh.point_scalars.end());
    std::cout << file << " (image volume)\n  voxels: " << mesh.points.size() << ", values in [" << *lo << ", " << *hi << "]\n";
    print_bounds(bounds_of(mesh));
    std::cout << "  as tetrahedra: " << mesh.tets.size() << " (6 per cell between 8 voxel centres), " << mesh.points.size()
              << " points\n  GPU memory (mesh buffers): " << double(io::estimated_gpu_bytes(mesh.tets.size(), mesh.points.size())) / 1048576.0
              << " MiB\n";
    return kOk;
  }
  if (io::is_surface_path(file)) {
    const SurfaceMesh surface = io::read_surface(file);
    const io::SurfaceCheck check = io::check_surface(surface);
    Bounds b;
    b.min = b.max = surface.points.front();
    for (const auto& p : surface.points) {
      b.min = glm::min(b.min, p);
      b.max = glm::max(b.max, p);
    }
    std::cout << file << " (surface)\n  triangles: " << surface.triangles.size() << ", points: " << surface.points.size() << "\n";
    print_bounds(b);
    if (check.closed()) {
      std::cout << "  closed: yes; rendering fills it with tetrahedra by TetGen (-pq1.414 unless --tetgen-* say otherwise)\n";
    } else {
      std::cout << "  closed: no: " << check.boundary_edges << " boundary (hole) edges, " << check.nonmanifold_edges
                << " non-manifold edges, the first near (" << check.first_problem.x << ", " << check.first_problem.y << ", "
                << check.first_problem.z << "); --fill-holes closes holes before TetGen\n";
    }
    return kOk;
  }
  std::cout << format_dataset_info(file, io::describe_dataset(file));
  return kOk;
}

int cmd_view(const std::vector<std::string>& args) {
  std::vector<std::string> value_options = with_camera({"size", "frames", "device"});
  value_options.insert(value_options.end(), kVolumeOptions.begin(), kVolumeOptions.end());
  ParsedArgs a = parse(args, 1, value_options, {"validate", "help", "shared-vertices", "fill-holes"});
  if (a.flags.count("help")) { std::cout << kViewHelp; return kOk; }
  VolumeChoice choice = volume_choice(a);
  if (choice.mode == "reference") throw InputError("--mode reference", "runs on the CPU: use `prismoid render --mode reference`");
  const TetMesh& mesh = choice.mesh;
  ViewerOptions options;
  if (a.has("size")) {
    const VkExtent2D s = parse_size(a.values.at("size"));
    options.width = s.width;
    options.height = s.height;
  }
  options.validation = a.flags.count("validate") > 0;
  options.device_index = parse_device(a);
  options.settings = choice.settings;
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
    else if (args.size() > 1 && args[1] == "info") std::cout << kInfoHelp;
    else std::cout << kUsage;
    return kOk;
  }
  if (verb == "devices") return cmd_devices(args);
  if (verb == "render") return cmd_render(args);
  if (verb == "view") return cmd_view(args);
  if (verb == "convert") return cmd_convert(args);
  if (verb == "info") return cmd_info(args);
  if (verb.rfind("--", 0) == 0) {  // options without a verb: the default verb
    std::vector<std::string> with_verb{display_available() ? "view" : "render"};
    with_verb.insert(with_verb.end(), args.begin(), args.end());
    return with_verb.front() == "view" ? cmd_view(with_verb) : cmd_render(with_verb);
  }
  throw InputError(verb, "unknown verb (verbs: view, render, convert, info, devices, help)");
}

}  // namespace

int run_cli(const std::vector<std::string>& args) {
  try {
    return dispatch(args);
  } catch (const InputError& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kBadInput;
  } catch (const io::Cancelled& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kCancelled;
  } catch (const vk::NoSuitableDevice& e) {
    std::cerr << "prismoid: no suitable Vulkan device: " << e.what() << "\n";
    return kNoDevice;
  } catch (const std::exception& e) {
    std::cerr << "prismoid: " << e.what() << "\n";
    return kFailure;
  }
}

}  // namespace prismoid::app
