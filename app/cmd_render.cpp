// `prismoid render`: one image headless, on the GPU or the CPU reference, with its timings.
#include <chrono>
#include <iostream>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/backend_cache.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/frame_image.hpp"
#include "app/common/frame_stats_writer.hpp"
#include "app/common/output_files.hpp"
#include "app/common/reference_accuracy.hpp"
#include "app/common/volume_option_table.hpp"
#include "app/common/volume_options.hpp"
#include "io/image_io.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

const char* const kRenderHelpHead =
    "usage: prismoid render [FILE] --output OUT.png|OUT.pfm [options]\n"
    "\n"
    "No output may be a file the command reads (nor a link to one) or another output; all are written\n"
    "beside their names and renamed together once every one is written, so a failure or Ctrl-C\n"
    "leaves none of them.\n"
    "\n"
    "  --output PATH        image to write: .png (display colour, sRGB) or .pfm (the quantity, float32)\n"
    "  --stats PATH.json    write a JSON file with the device, the passes that ran and their GPU times,\n"
    "                       and the frame plan: each planned pass with its reason, each skipped one with why\n";

// After --quantity.
const char* const kRenderHelpView =
    "  --size WxH           image size in pixels (default 800x600)\n"
    "  --eye x,y,z --target x,y,z --up x,y,z --fovy DEG --near N\n"
    "                       camera (default: framing the data from +z, fovy 40; a placed eye without\n"
    "                       --near gets a near plane before the data nearest it)\n"
    "  --depth-limit D.pfm  where each pixel's ray ends, as a depth along the viewing axis (a grey PFM of\n"
    "                       --size, row 0 at the top; +inf where nothing is): opaque geometry in front of or\n"
    "                       inside the volume. Not with marching or isosurfaces\n";

// After --volume-backend's lines.
const char* const kRenderHelpDevice =
    "  --device N           use Vulkan device N (see `prismoid devices`)\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n";

// After the mesh backend's options.
const char* const kRenderHelpTiming =
    "  --frames N           render N timed frames after 2 s of warm-up frames (the GPU leaves its idle\n"
    "                       clock); times are the median, with the best and worst beside them, and the\n"
    "                       SM clock meanwhile where nvidia-smi is on PATH (default 1, no warm-up)\n"
    "  --reference-error    (volume modes) also compute the CPU double-precision reference of the same\n"
    "                       frame and print how far the image is from it (RMSE and largest difference\n"
    "                       of the display colour for color, of the quantity otherwise; FLIP for\n"
    "                       color) and what it cost; --stats gets them as \"reference_error\"\n";

// The datasets, around the options that load them.
const char* const kRenderHelpFiles =
    "FILE: an unstructured grid (.vtu, legacy .vtk, multiblock .vtm, parallel .pvtu; cells other than\n"
    "tetrahedra are split into conforming tetrahedra, with a note), or field:NAME[:N], an analytic field\n"
    "in world coordinates bounded by the box [-1,1]^3 split into N^3 cubes of 6 tetrahedra (default\n"
    "N = 4: each cell holds a strongly non-linear field). NAME: marschner-lobb (Marschner & Lobb 1994,\n"
    "f_M = 6, alpha = 0.25, values in [0,1]), blobs (three Gaussian blobs), sphere (one Gaussian blob:\n"
    "its isosurfaces are spheres), linear. The field is the extinction (times --density-scale) and\n"
    "the color scalar; the other GPU modes render its linear interpolant at the mesh points, the\n"
    "marching modes and the CPU reference the field itself. grid:NAME[:N] samples that field at N^3 points\n"
    "of [-1,1]^3 (default 32) and renders the samples' trilinear interpolant as voxel data is: marched\n"
    "inside the blocks of 8^3 samples that hold a value above 1/1000 of the largest, each block 6\n"
    "tetrahedra. FILE may also be a closed triangle surface\n"
    "(.vtp .stl .obj .ply .off), filled with tetrahedra by TetGen (extinction 1 per cell):\n";
const char* const kRenderHelpImages =
    "or an image volume (.vti .mhd .mha, .inr/.inr.gz as in CGAL's data): each cell between 8 voxel\n"
    "centres becomes 6 tetrahedra, voxel values are point values (--array picks the .vti/.mhd array);\n";
const char* const kRenderHelpVdb =
    "or an OpenVDB file (.vdb): a float grid's voxels the same way, cells around its active voxels\n"
    "(a level set's inside is filled: extinction 0 outside, rising to 1 across the inner band);\n"
    "with a marching --mode the grid is marched instead inside its active regions (leaf nodes\n"
    "and tiles, 6 tetrahedra each; a level set: its whole box), and the CPU reference marches its\n"
    "trilinear field;\n";
const char* const kRenderHelpExodus =
    "or an Exodus II file (.exo .e .ex2 .exii .g .gen, read by VTK's Exodus reader as ParaView reads it):\n"
    "its element blocks that hold 3D cells, merged with their shared nodes, nodal variables as point\n"
    "arrays and element variables as cell arrays, displacements applied; side sets, node sets, and\n"
    "blocks without 3D cells are not drawn (a note names them);\n";
const char* const kRenderHelpSeries =
    "or a time series, of which one step is drawn: a .pvd (a ParaView data collection: one mesh file\n"
    "per time step, beside it) or a numbered series, its file name with a * for the number (quoted:\n"
    "'flow_*.vtu', the files flow_000.vtu, flow_001.vtu... in the order of their numbers, at times\n"
    "0, 1, 2...); a series' or an Exodus file's step:\n";
const char* const kRenderHelpBall =
    "ball[:S] is a unit ball of constant extinction (an icosphere subdivided S times, default 3, one\n"
    "tetrahedron per boundary triangle): its optical depth is sigma times the chord, in closed form.\n"
    "With no FILE the embedded default dataset is rendered; asked for no --quantity and no --mode, in\n"
    "color, in exact order (interval-exact-order).\n";

// Where an option's explanation starts in render's help.
constexpr size_t kIndent = 23;

// The --mode lines of the help, from the volume mode table.
std::string volume_modes_help() {
  std::vector<std::pair<std::string, std::string>> rows;
  for (const frame::VolumeMode& m : frame::volume_mode_table()) rows.emplace_back(m.name, m.summary);
  rows.emplace_back("SURFACE", "a surface mode (listed below)");
  std::string help = help_table("--mode MODE", kIndent, rows);
  help.append(kIndent, ' ').append("(default: ").append(frame::default_volume_mode(volume::Quantity::Transmittance).name).append("; ");
  help.append(frame::default_volume_mode(volume::Quantity::Color).name).append(" for --quantity color)\n");
  return help;
}

// The --volume-backend lines of the help, from the volume backend table.
std::string volume_backends_help() {
  std::vector<std::pair<std::string, std::string>> rows;
  for (const volume::VolumeBackendInfo* b : volume::volume_backend_table()) rows.emplace_back(b->name, b->summary);
  rows.emplace_back("auto", "the fastest GPU backend on this device, by a calibration frame kept in $XDG_CACHE_HOME/prismoid/backends.json");
  std::string help = help_table("--volume-backend B", kIndent, rows);
  help.append(kIndent, ' ').append("(default: mesh; cpu is what --mode reference draws)\n");
  return help;
}

}  // namespace

const char* const kRenderMixedHelp =
    "\nA volume inside its surfaces (render VOLUME SURFACE... --output OUT): every surface opaque, the\n"
    "volume's rays ending at the first one; --mode names the volume's mode (interval modes, or reference:\n"
    "the whole frame on the CPU), --surface-mode the surfaces' (any GPU surface mode above, default\n"
    "forward), --shadows on|off whether they cast shadows (default: on where the device traces rays\n"
    "and a light casts them); --reference-error measures the frame against its CPU reference (the\n"
    "surfaces' direct light). .png: the composite; .pfm: the volume's quantity up to the surfaces\n"
    "(color: the composite's RGB). `prismoid info VOLUME SURFACE... --plan` explains the frame.\n";

std::string render_help() {
  using G = VolumeOptionGroup;
  // The dataset options' help starts further in, under the prose that introduces them.
  constexpr size_t kFileIndent = 27;
  // (append, not +: GCC 12 warns falsely about + of strings here, -Warray-bounds)
  std::string help = kRenderHelpHead;
  help.append(volume_modes_help()).append(volume_options_help(G::Quantity, kIndent)).append(kRenderHelpView);
  help.append(volume_backends_help()).append(kRenderHelpDevice).append(volume_options_help(G::Mesh, kIndent)).append(kRenderHelpTiming);
  help.append("\n").append(volume_options_help(G::Data, kIndent));
  help.append("\n  marching modes only:\n").append(volume_options_help(G::March, kIndent));
  help.append("\n  color only:\n").append(volume_options_help(G::Color, kIndent));
  help.append("\n").append(kRenderHelpFiles).append(volume_options_help(G::Tetgen, kFileIndent)).append(kRenderHelpImages);
  help.append(volume_options_help(G::Image, kFileIndent)).append(kRenderHelpVdb).append(volume_options_help(G::Vdb, kFileIndent));
  help.append(kRenderHelpExodus).append(volume_options_help(G::Exodus, kFileIndent));
  help.append(kRenderHelpSeries).append(volume_options_help(G::Time, kFileIndent));
  help.append(kRenderHelpBall).append(surface_render_help()).append(kRenderMixedHelp);
  return help;
}


const std::vector<std::string> kRenderFlags = [] {
  std::vector<std::string> flags = {"validate", "help", "reference-error"};
  for (const std::string& f : volume_flag_options()) flags.push_back(f);
  return flags;
}();

int cmd_render(const std::vector<std::string>& args) {
  if (mixed_scene_named(args)) return cmd_render_mixed(args);
  if (const surface::SurfaceMode* surface = surface_mode_named(args))
    return cmd_render_surface(args, *surface);
  std::vector<std::string> value_options = with_camera({"output", "stats", "size", "device", "frames", "depth-limit"});
  value_options.insert(value_options.end(), kVolumeOptions.begin(), kVolumeOptions.end());
  ParsedArgs a = parse(args, 1, value_options, kRenderFlags);
  if (a.flags.count("help")) { std::cout << render_help(); return kOk; }
  if (!a.has("output")) throw InputError("render", "--output OUT.png|OUT.pfm is required");
  const std::string output = a.values.at("output");
  OutputFiles files;
  declare_render_files(files, a);
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : VkExtent2D{800, 600};
  const auto device_index = parse_device(a);
  const uint32_t frames = a.has("frames") ? parse_uint("frames", a.values.at("frames")) : 1;
  if (frames == 0 || frames > 10000) throw InputError("--frames", "must be between 1 and 10000");
  const VolumeChoice choice = volume_choice(a);
  const TetMesh& mesh = choice.mesh;
  const frame::VolumeMode& mode = *choice.mode;
  if (a.flags.count("reference-error") && !mode.gpu())
    throw InputError("--reference-error", "--mode " + std::string(mode.name) + " is the reference itself");
  const volume::Quantity quantity = choice.quantity;
  const bool color = quantity == volume::Quantity::Color;
  const bool field = field_of(a).has_value();  // an analytic field: its own CPU reference
  const Camera camera = camera_from(a, bounds_of(mesh));
  mixed::SceneSettings scene_settings;
  scene_settings.size = size;
  scene_settings.volume_mode = &mode;
  scene_settings.volume = choice.settings;
  if (a.has("depth-limit")) scene_settings.volume.resolve.depth_limit = read_depth_limit(a.values.at("depth-limit"), size);
  scene_settings.volume_backend_auto = choice.backend_auto;
  scene_settings.frames = frames;
  mixed::SceneRenderer renderer({.volume = &mesh, .analytic_field = field},
                                {.validation = a.flags.count("validate") > 0, .index = device_index}, resolve_auto_backend);
  const mixed::SceneFrame drawn = renderer.render(camera, scene_settings);
  const frame::OffscreenFrame& result = *drawn.volume;
  const vk::Instance* instance = renderer.instance();
  const size_t validation_messages = instance ? instance->validation_log().count() : 0;
  // What the image's accuracy is: the same frame on the CPU, in double precision and exact order.
  std::optional<ReferenceAccuracy> accuracy;
  if (a.flags.count("reference-error")) {
    const auto start = std::chrono::steady_clock::now();
    const mixed::SceneFrame ref = renderer.reference(camera, scene_settings, drawn);
    accuracy = measure_accuracy(result, *ref.volume, quantity,
                                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }

  const io::FloatImage image = frame_image(result, output, color);
  files.write(output, [&](const std::string& file) { io::write_image(file, image); });
  for (const std::string& w : result.report.warnings) std::cerr << "prismoid: warning: " << w << "\n";

  // What the render says is printed once its files are in place: a write that fails after this
  // point (the stats, the rename) must not follow a "wrote".
  const FrameOutput said{.image = output, .validation_messages = validation_messages, .accuracy = accuracy ? &*accuracy : nullptr};
  if (a.has("stats"))
    files.write(a.values.at("stats"), [&](const std::string& file) { write_stats(file, frame_json(drawn.stats, said)); });
  files.commit();
  std::cout << frame_text(drawn.stats, said);
  return instance ? validation_exit(*instance) : kOk;
}

}  // namespace prismoid::app
