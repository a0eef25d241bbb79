// `prismoid view`: the window.
#include <algorithm>
#include <chrono>
#include <map>
#include <iostream>
#include <string>

#include <glm/common.hpp>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/dataset_loader.hpp"
#include "app/common/surface_args.hpp"
#include "app/common/terminal_progress.hpp"
#include "app/common/volume_option_table.hpp"
#include "app/common/volume_options.hpp"
#include "app/viewer/recent_files.hpp"
#include "app/viewer/surface_viewer.hpp"
#include "app/viewer/viewer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "scene/input_error.hpp"
#include "scene/surface_generators.hpp"

namespace prismoid::app {

namespace {

// A dataset after the first on the command line, loaded before the window opens (with the
// terminal's progress bar and Ctrl-C) as the first one is.
Dataset load_for_view(const LoadRequest& request, bool color) {
  TetMesh mesh;
  {
    TerminalProgress progress(request.path);
    mesh = load_dataset(request, progress.callback());
    progress.throw_if_cancelled(request.path);
  }
  validate(mesh);
  Dataset d = make_dataset(std::move(mesh), field_of_request(request));
  attach_time(d, request);
  if (color && !d.has_scalars)
    throw InputError(request.path, "has no scalar field for --quantity color, which needs one in every dataset shown "
                                   "(choose a point or cell array with --array NAME)");
  return d;
}

Bounds union_bounds(const std::vector<Dataset>& datasets) {
  Bounds b = datasets.front().bounds;
  for (const Dataset& d : datasets) {
    b.min = glm::min(b.min, d.bounds.min);
    b.max = glm::max(b.max, d.bounds.max);
  }
  return b;
}

}  // namespace

bool window_available() { return display_available(); }

namespace {

const char* const kViewHelpHead =
    "usage: prismoid view [FILE...] [options]\n"
    "\n"
    "Surface scenes (cornell-box, furnace:A, or a surface FILE with a surface --mode, as listed by\n"
    "render --help) open the surface window: its panel lists the surface modes this device draws\n"
    "(M cycles them) with each pass's GPU time and the frame plan. --max-triangle-pixels P splits\n"
    "its triangles until none spans more than P pixels of the first view (as block atlases want).\n"
    "\n"
    "Several FILEs open together in one scene (drawn as their union; each can be hidden in the\n"
    "panel's Data section). More can be opened from the window: the path box, the recent files,\n"
    "or by dropping files onto it; they load in the background with a progress bar and Cancel.\n"
    "\n"
    "  --size WxH           initial window size (default 1280x800)\n";

// Options after the volume options.
const char* const kViewHelpTail =
    "  --eye/--target/--up/--fovy/--near   initial camera, as for render\n"
    "  --frames N           close after N frames (for scripted runs)\n"
    "  --script FILE        drive the window from a command file (see docs/user-guide.md)\n"
    "  --no-ui              start with the panels hidden (H shows them)\n"
    "  --volume-backend B   a GPU backend of render's (mesh, the default, or compute) or auto; switchable in\n"
    "                       the mode panel\n"
    "  --device N           use Vulkan device N\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n"
    "\n"
    "Mouse: left drag rotates, shift+left or middle drag pans, right drag or wheel zooms.\n"
    "Keys: R fit, X/Y/Z (shift: negative) axis views, F fly (WASD/QE move, drag looks), C copy the\n"
    "camera as render options, P screenshot, H hide the panels, Esc close.\n";

}  // namespace

std::string view_help() {
  using G = VolumeOptionGroup;
  // The volume options from the option table: what render takes, but the CPU reference's mode.
  return kViewHelpHead + wrap_words("  ", "--mode, " + volume_option_list({G::Quantity, G::Data, G::Mesh, G::March, G::Color}), 2) +
         "                       what to show and how, as for render (the GPU modes: not the CPU reference)\n" +
         wrap_words("  ", volume_option_list({G::Tetgen, G::Image, G::Vdb, G::Exodus, G::Time}), 2) +
         "                       how a FILE loads, as for render\n" + kViewHelpTail;
}

namespace {

// A surface scene opens the surface window: a built-in one (cornell-box, furnace:A), or any
// FILE with a surface mode (--mode forward, htex...; a surface file without it is tetrahedralized
// for the volume modes, as render does).
bool wants_surface_window(const ParsedArgs& a) {
  if (a.has("mode")) return surface::find_surface_mode(a.values.at("mode")) != nullptr;
  return !a.files.empty() && is_named_surface_scene(a.files.front());
}

ViewerOptions window_options(const ParsedArgs& a) {
  ViewerOptions options;
  if (a.has("size")) {
    const VkExtent2D s = parse_size(a.values.at("size"));
    options.width = s.width;
    options.height = s.height;
  }
  options.validation = a.flags.count("validate") > 0;
  options.device_index = parse_device(a);
  options.show_ui = a.flags.count("no-ui") == 0;
  if (a.has("script")) options.script = read_script(a.values.at("script"));
  if (a.has("frames")) {
    options.max_frames = parse_uint("frames", a.values.at("frames"));
    // 0 is the window's "until closed" inside; typed, it would never close, where render refuses it.
    if (options.max_frames == 0) throw InputError("--frames", "must be at least 1 (leave it out to keep the window open until closed)");
  }
  return options;
}

// What the window was started from: its outputs may not replace these.
std::vector<std::string> window_inputs(const ParsedArgs& a) {
  std::vector<std::string> inputs = a.files;
  for (const char* option : {"tf", "script"})
    if (a.has(option)) inputs.push_back(a.values.at(option));
  return inputs;
}

int report_window(const ViewerReport& report, const ViewerOptions& options, double seconds) {
  std::cout << "presented " << report.frames_presented << " frames on " << report.device_name << " in " << seconds << " s ("
            << report.frames_presented / seconds << " frames per second, window set-up included)\n";
  if (!report.moving_frames.empty()) {  // how the window kept up while the camera moved
    std::vector<double> ms;
    std::map<uint32_t, size_t> levels;
    for (const auto& [frame_ms, level] : report.moving_frames) {
      ms.push_back(frame_ms);
      ++levels[level];
    }
    std::sort(ms.begin(), ms.end());
    const double median = ms[ms.size() / 2];
    std::cout << "  while the camera moved: " << ms.size() << " frames, median " << median << " ms from recording to end ("
              << 1000.0 / median << " frames per second), worst " << ms.back() << " ms; resolution:";
    for (const auto& [level, count] : levels)
      std::cout << (level > 4 ? std::string(" coarser proxy (10^3 cubes) at 1/8")
                    : level > 3 ? std::string(" coarse proxy (16^3 cubes) at 1/8")
                                : " 1/" + std::to_string(1u << level)) << " x" << count;
    std::cout << "\n";
    if (!report.still_frames_ms.empty())
      std::cout << "  the first frame after it stopped (full resolution): " << report.still_frames_ms.front() << " ms\n";
  }
  std::cout << "  input was read at least every " << report.longest_input_gap_ms << " ms (" << report.input_reads_while_drawing
            << " readings while frames were drawn)\n";
  if (options.validation && report.validation_messages > 0) {
    std::cerr << "prismoid: the validation layer reported " << report.validation_messages << " message(s)\n";
    return kValidationMessages;
  }
  return kOk;
}

int view_surface(const ParsedArgs& a) {
  if (a.files.size() != 1) throw InputError("view", "the surface window shows one scene: give one FILE");
  const std::string mode = a.has("mode") ? a.values.at("mode") : std::string(surface::surface_mode_table().front().name);
  if (!surface::find_surface_mode(mode)->gpu())
    throw InputError("--mode " + mode, "runs on the CPU: use `prismoid render --mode " + mode + " --output OUT.pfm`");
  const SurfaceScene loaded = surface_scene_from(a, mode);
  ViewerOptions options = window_options(a);
  options.inputs = window_inputs(a);
  options.mode = a.has("mode") ? a.values.at("mode") : "";
  const Camera camera = surface_camera(a, loaded);
  const SurfaceScene scene = refined_for_view(a, loaded, camera, options.width, options.height);
  bool any_camera = false;
  for (const auto& k : kCameraOptions) any_camera = any_camera || a.has(k);
  if (any_camera) options.camera = camera;
  if (!display_available()) throw InputError("view", "no display (DISPLAY is not set); use `prismoid render --output X.png`");
  const auto start = std::chrono::steady_clock::now();
  const ViewerReport report = run_surface_viewer(with_default_lighting(scene, camera), options);
  return report_window(report, options, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace

int cmd_view(const std::vector<std::string>& args) {
  std::vector<std::string> value_options = with_camera({"size", "frames", "device", "script", "max-triangle-pixels"});
  value_options.insert(value_options.end(), kVolumeOptions.begin(), kVolumeOptions.end());
  std::vector<std::string> flags = {"validate", "help", "no-ui"};
  for (const std::string& f : volume_flag_options()) flags.push_back(f);
  ParsedArgs a = parse(args, 1, value_options, flags);
  if (a.flags.count("help")) { std::cout << view_help(); return kOk; }
  if (wants_surface_window(a)) return view_surface(a);
  if (a.has("max-triangle-pixels")) throw InputError("--max-triangle-pixels", "splits a surface scene's triangles; these FILEs open as volumes");
  ParsedArgs first = a;  // the first dataset decides the settings (the transfer function's range among them)
  if (first.files.size() > 1) first.files.resize(1);
  VolumeChoice choice = volume_choice(first);
  const std::string mode(choice.mode->name);
  if (!choice.mode->gpu()) {
    // The window draws on the GPU; the CPU backend's frames are `render`'s (and the difference view's).
    const std::string asked = a.has("mode") ? "--mode " + mode : "--volume-backend " + a.values.at("volume-backend");
    throw InputError(asked, "runs on the CPU: use `prismoid render " + asked + "` (the window's difference view shows the CPU reference)");
  }
  if (a.files.size() > 1 && choice.settings.resolve.march.enabled)
    throw InputError("--mode " + mode, "marches the field of one dataset: give one FILE");
  const bool color = choice.settings.resolve.quantity == volume::Quantity::Color;
  ViewState state;
  state.datasets.push_back(make_dataset(std::move(choice.mesh), field_of(first)));
  attach_time(state.datasets.back(), load_request_from(first, color));
  for (size_t i = 1; i < a.files.size(); ++i) state.datasets.push_back(load_for_view(load_request_from(a, a.files[i], color), color));
  ViewerOptions options = window_options(a);
  options.inputs = window_inputs(a);
  options.settings = choice.settings;
  options.mode = mode;
  options.backend_auto = choice.backend_auto;
  bool any_camera = false;
  for (const auto& k : kCameraOptions) any_camera = any_camera || a.has(k);
  if (any_camera) options.camera = camera_from(a, union_bounds(state.datasets));
  if (!display_available()) throw InputError("view", "no display (DISPLAY is not set); use `prismoid render --output X.png`");
  options.open_defaults.role = color ? io::ArrayRole::Scalars : io::ArrayRole::Extinction;
  if (a.has("density-scale")) options.open_defaults.density_scale = parse_double("density-scale", a.values.at("density-scale"));
  options.recent_file = recent_files_path();
  for (const std::string& file : a.files) remember_opened(options.recent_file, file);
  const auto start = std::chrono::steady_clock::now();
  const ViewerReport report = run_viewer(std::move(state), options);
  return report_window(report, options, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

}  // namespace prismoid::app
