// `prismoid bench`: what accuracy costs in time. Every case (app/bench/bench_cases.hpp) is
// rendered on the GPU, timed over repeated frames after a warm-up, and measured against the CPU
// double-precision reference, which is computed once per dataset, quantity and image size and
// shared by every mode measured against it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <glm/geometric.hpp>
#include <unistd.h>

#include "app/bench/bench_cases.hpp"
#include "app/bench/bench_table.hpp"
#include "app/cli.hpp"
#include "app/cli_args.hpp"
#include "app/commands.hpp"
#include "app/reference_frame.hpp"
#include "app/volume_options.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/image_error.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

const char* const kBenchHelp =
    "usage: prismoid bench [FILE...] --out DIR [options]\n"
    "\n"
    "Renders each dataset in each configuration on the GPU, times it, and measures its error against\n"
    "the CPU double-precision reference (computed once per dataset, quantity and image size). Writes\n"
    "DIR/bench.csv (one row per measurement) and DIR/report.md (the machine, the command, a table per\n"
    "dataset; * marks the Pareto-optimal rows: no other row of the same dataset, quantity and image\n"
    "size is both at least as fast and at least as accurate).\n"
    "\n"
    "  --out DIR            folder for bench.csv and report.md (created if missing)\n"
    "  --quick              96x72, 3 frames, one or two settings per sweep: a smoke test in a minute\n"
    "  --size WxH           image size (default 400x300)\n"
    "  --frames N           timed frames after one warm-up frame (default 10); times are the median,\n"
    "                       with min and max\n"
    "  --sweeps LIST        comma-separated subset of: modes, tetlet-size, preintegration, image-size,\n"
    "                       march-step, cells (default: all)\n"
    "  --max-cells N        the cell-count sweep's largest mesh (default 2000000; the sweep splits\n"
    "                       field:marschner-lobb into N^3 cubes, 6 cells each, N = 6, 12, 24, 48, 96, 128)\n"
    "  --device N           use Vulkan device N (see `prismoid devices`)\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n"
    "  --density-scale S --tf PRESET|FILE --tf-range LO,HI --array NAME --component C --background R,G,B\n"
    "                       as for `prismoid render`, applied to every configuration of the FILEs\n"
    "\n"
    "Sweeps, per FILE: modes (optical depth and transmittance with --mode interval; color with\n"
    "interval, interval-sorted and interval-exact-order), tetlet-size (1, 4, 8 beside the default 16),\n"
    "preintegration (table sizes 16, 64, 256 beside exact segments); on the first FILE: image-size\n"
    "(half and twice --size); on field:marschner-lobb: march-step (interval-march at 1/25 to 1/400 of\n"
    "the diagonal, beside its tetrahedra) and cells (N^3 cubes). Errors: RMSE, largest absolute error,\n"
    "PSNR and SSIM of the quantity (peak: the reference's largest optical depth, or 1 for\n"
    "transmittance) or of the display RGB (peak 1) for color; non-finite values are counted, never\n"
    "averaged. FILE: anything `prismoid render` reads (default: the embedded default dataset and ball:2).\n";

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The per-pass medians over the frames, as "name=ms;name=ms".
std::string pass_medians(const std::vector<std::vector<vk::PassTiming>>& frames) {
  std::ostringstream s;
  for (size_t i = 0; i < frames.front().size(); ++i) {
    const std::string& name = frames.front()[i].name;
    std::vector<double> ms;
    for (const auto& f : frames)
      for (const auto& p : f)
        if (p.name == name) ms.push_back(p.gpu_ms);
    s << (i ? ";" : "") << name << "=" << json_number(median(ms));
  }
  return s.str();
}

// The signal range the PSNR is relative to: the reference's largest optical depth, else 1.
double peak_of(const frame::OffscreenFrame& ref, volume::Quantity q) {
  if (q != volume::Quantity::OpticalDepth) return 1.0;
  double peak = 0.0;
  for (float v : ref.quantity)
    if (std::isfinite(v)) peak = std::max(peak, double(v));
  return peak;
}

double ssim_of(const frame::OffscreenFrame& gpu, const frame::OffscreenFrame& ref, volume::Quantity q) {
  if (q == volume::Quantity::Color) return reference::ssim(gpu.display, ref.display, ref.width, ref.height, 1.0, 4, 3);
  return reference::ssim(gpu.quantity, ref.quantity, ref.width, ref.height, peak_of(ref, q), 1, 1);
}

reference::ImageError error_of(const frame::OffscreenFrame& gpu, const frame::OffscreenFrame& ref, volume::Quantity q) {
  if (q == volume::Quantity::Color) return reference::image_error(gpu.display, ref.display, 1.0, 4, 3);
  return reference::image_error(gpu.quantity, ref.quantity, peak_of(ref, q), 1, 1);
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// Loads each dataset once per way of loading it (as extinction or as the transfer function's
// scalar; a .vdb as voxels or as marched regions) and hands out copies.
class MeshCache {
 public:
  TetMesh operator()(const ParsedArgs& a, bool scalar_field) {
    std::string key = (a.files.empty() ? std::string() : a.files.front()) + (scalar_field ? "|scalar" : "|extinction");
    if (a.has("mode")) key += a.values.at("mode").rfind("interval-march", 0) == 0 ? "|march" : "";
    auto it = meshes_.find(key);
    if (it == meshes_.end()) it = meshes_.emplace(key, load_scene(a, scalar_field)).first;
    return it->second;
  }
  void clear() { meshes_.clear(); }

 private:
  std::map<std::string, TetMesh> meshes_;
};

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof(name) - 1) != 0) return {};
  return name;
}

}  // namespace

int cmd_bench(const std::vector<std::string>& args) {
  const std::vector<std::string> passed_through = {"density-scale", "tf", "tf-range", "array", "component", "background"};
  std::vector<std::string> value_options = {"out", "size", "frames", "device", "sweeps", "max-cells"};
  value_options.insert(value_options.end(), passed_through.begin(), passed_through.end());
  const ParsedArgs a = parse(args, 1, value_options, {"quick", "validate", "help"});
  if (a.flags.count("help")) { std::cout << kBenchHelp; return kOk; }
  if (!a.has("out")) throw InputError("bench", "--out DIR is required");
  bench::BenchPreset preset;
  preset.quick = a.flags.count("quick") > 0;
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : preset.quick ? VkExtent2D{96, 72} : VkExtent2D{400, 300};
  preset.size = {size.width, size.height};
  preset.max_cells = a.has("max-cells") ? parse_uint("max-cells", a.values.at("max-cells")) : 2'000'000;
  const uint32_t frames = a.has("frames") ? parse_uint("frames", a.values.at("frames")) : preset.quick ? 3 : 10;
  if (frames == 0 || frames > 10000) throw InputError("--frames", "must be between 1 and 10000");
  const std::vector<std::string> all_sweeps = {"modes", "tetlet-size", "preintegration", "image-size", "march-step", "cells"};
  const std::vector<std::string> sweeps = a.has("sweeps") ? split_list(a.values.at("sweeps")) : all_sweeps;
  for (const auto& s : sweeps)
    if (std::find(all_sweeps.begin(), all_sweeps.end(), s) == all_sweeps.end())
      throw InputError("--sweeps", "unknown sweep '" + s + "' (modes, tetlet-size, preintegration, image-size, march-step, cells)");
  const std::filesystem::path out_dir = a.values.at("out");
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError(out_dir.string(), "cannot create the output folder: " + ec.message());

  const std::vector<std::string> datasets = a.files.empty() ? std::vector<std::string>{"", "ball:2"} : a.files;
  std::vector<bench::BenchCase> cases = bench::bench_cases(datasets, preset);
  std::erase_if(cases, [&](const bench::BenchCase& c) { return std::find(sweeps.begin(), sweeps.end(), c.sweep) == sweeps.end(); });

  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});

  MeshCache meshes;
  // By dataset, quantity and size: the reference image and its CPU time.
  std::map<std::string, std::pair<frame::OffscreenFrame, double>> references;
  std::string loaded_dataset;
  std::vector<bench::BenchRow> rows;
  for (const bench::BenchCase& c : cases) {
    if (c.dataset != loaded_dataset) {  // cases come grouped by dataset: keep one dataset's meshes at a time
      meshes.clear();
      loaded_dataset = c.dataset;
    }
    ParsedArgs one;
    if (!c.dataset.empty()) one.files.push_back(c.dataset);
    const bool user_file = std::find(datasets.begin(), datasets.end(), c.dataset) != datasets.end();
    if (user_file)
      for (const auto& o : passed_through)
        if (a.has(o)) one.values[o] = a.values.at(o);
    one.values["quantity"] = c.quantity;
    one.values["mode"] = c.mode;
    for (const auto& [k, v] : c.options) one.values[k] = v;
    if (auto step = one.values.find("march-step"); step != one.values.end() && step->second.rfind("diagonal/", 0) == 0) {
      const Bounds b = bounds_of(meshes(one, c.quantity == "color"));  // "diagonal/N": N steps across the box
      step->second = json_number(glm::length(b.max - b.min) / std::stod(step->second.substr(9)));
    }
    std::optional<VolumeChoice> chosen;
    try {
      chosen = volume_choice(one, std::ref(meshes));
    } catch (const InputError& e) {
      // A dataset without a scalar array has no colour; its other quantities are still measured.
      if (c.quantity != "color") throw;
      std::cerr << "prismoid: bench: skipping color " << c.mode << " " << bench::settings_label(c) << " of "
                << (c.dataset.empty() ? "the default dataset" : c.dataset) << ": " << e.what() << "\n";
      continue;
    }
    const VolumeChoice& choice = *chosen;
    const Camera camera = camera_from(one, bounds_of(choice.mesh));
    const volume::ResolveSettings& resolve = choice.settings.resolve;
    const VkExtent2D extent{c.size.width, c.size.height};

    const std::string ref_key = c.dataset + "|" + c.quantity + "|" + std::to_string(extent.width) + "x" + std::to_string(extent.height);
    auto ref = references.find(ref_key);
    if (ref == references.end()) {
      const auto start = std::chrono::steady_clock::now();
      frame::OffscreenFrame image = field_of(one) ? render_field_reference(choice.mesh, camera, resolve, extent)
                                                  : render_reference(choice.mesh, camera, resolve, extent);
      ref = references.emplace(ref_key, std::make_pair(std::move(image), ms_since(start))).first;
    }

    frame::FrameRenderer renderer(device, choice.mesh);
    renderer.render_offscreen(camera, choice.settings, extent);  // warm-up: caches, clocks, first-use work
    std::vector<std::vector<vk::PassTiming>> timings;
    std::vector<double> totals, cpu;
    frame::OffscreenFrame result;
    for (uint32_t i = 0; i < frames; ++i) {
      renderer.forget_history();  // each timed frame costs what a moving camera's does: no order reused
      result = renderer.render_offscreen(camera, choice.settings, extent);
      double total = 0.0, cpu_total = 0.0;
      for (const auto& p : result.passes) total += p.gpu_ms;
      for (const auto& p : result.report.cpu_passes) cpu_total += p.gpu_ms;
      totals.push_back(total);
      cpu.push_back(cpu_total);
      timings.push_back(result.passes);
    }

    bench::BenchRow m;
    m.dataset = choice.mesh.name;
    m.cells = choice.mesh.tets.size();
    m.sweep = c.sweep;
    m.quantity = c.quantity;
    m.mode = c.mode;
    m.settings = bench::settings_label(c);
    m.ordering = result.report.ordering;
    m.width = extent.width;
    m.height = extent.height;
    m.frames = frames;
    m.ms_median = median(totals);
    m.ms_min = *std::min_element(totals.begin(), totals.end());
    m.ms_max = *std::max_element(totals.begin(), totals.end());
    m.cpu_ms = median(cpu);
    m.passes = pass_medians(timings);
    m.mesh_bytes = result.report.mesh_bytes;
    // The image is the last timed frame's: every frame draws the same cells from the same camera.
    m.error = error_of(result, ref->second.first, choice.quantity);
    m.ssim = ssim_of(result, ref->second.first, choice.quantity);
    m.reference_ms = ref->second.second;
    m.peak = peak_of(ref->second.first, choice.quantity);
    std::cout << m.dataset << " " << m.sweep << " " << m.quantity << " " << m.mode << " " << m.settings << " " << m.width << "x"
              << m.height << ": " << json_number(m.ms_median) << " ms GPU, RMSE " << json_number(m.error.rmse) << std::endl;
    rows.push_back(std::move(m));
  }
  bench::mark_pareto(rows);

  bench::ReportContext context;
  context.device = caps.name;
  context.driver = caps.driver_info;
  context.host = host_name();
  context.command = "prismoid";
  for (const auto& s : args) context.command += " " + s;
  bench::write_csv(out_dir / "bench.csv", rows);
  bench::write_report(out_dir / "report.md", rows, context);
  std::cout << "wrote " << (out_dir / "bench.csv").string() << " and " << (out_dir / "report.md").string() << "\n";
  return validation_exit(instance);
}

}  // namespace prismoid::app
