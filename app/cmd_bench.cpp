// `prismoid bench`: what accuracy costs in time. Every configuration is rendered on the GPU
// (timed over repeated frames after a warm-up) and measured against the CPU double-precision
// reference, which is computed once per dataset and quantity and shared by all modes.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

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
    "Renders each dataset in each configuration (quantity, mode, setting) on the GPU, times it, and\n"
    "measures its error against the CPU double-precision reference (computed once per dataset and\n"
    "quantity). Writes DIR/bench.csv (one row per measurement) and DIR/report.md (the machine, the\n"
    "command, a table per dataset sorted by GPU time; * marks the Pareto-optimal rows: no other row\n"
    "of the same quantity is both at least as fast and at least as accurate).\n"
    "\n"
    "  --out DIR            folder for bench.csv and report.md (created if missing)\n"
    "  --quick              96x72, 3 frames, the main configurations: a smoke test in seconds\n"
    "  --size WxH           image size (default 400x300)\n"
    "  --frames N           timed frames after one warm-up frame (default 10); times are the median,\n"
    "                       with min and max\n"
    "  --device N           use Vulkan device N (see `prismoid devices`)\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n"
    "  --density-scale S --tf PRESET|FILE --tf-range LO,HI --array NAME --component C --background R,G,B\n"
    "                       as for `prismoid render`, applied to every configuration\n"
    "\n"
    "Configurations: optical-depth and transmittance with --mode interval (optical depth also with\n"
    "--tetlet-size 1); color with --mode interval, interval-sorted, interval-exact-order, and\n"
    "interval-sorted with --preintegration-size 16 and 64. Errors: RMSE, largest absolute error and\n"
    "PSNR of the quantity (peak: the reference's largest optical depth, or 1 for transmittance) or\n"
    "of the display RGB (peak 1) for color; non-finite values are counted, never averaged.\n"
    "FILE: anything `prismoid render` reads (default: the embedded default dataset and ball:2).\n";

namespace {

struct BenchConfig {
  std::string quantity;
  std::string mode;
  std::vector<std::pair<std::string, std::string>> options;  // extra volume options
  bool in_quick = true;
};

std::vector<BenchConfig> bench_configs(bool quick) {
  std::vector<BenchConfig> all = {
      {"optical-depth", "interval", {}},
      {"optical-depth", "interval", {{"tetlet-size", "1"}}},
      {"transmittance", "interval", {}},
      {"color", "interval", {}},
      {"color", "interval-sorted", {}},
      {"color", "interval-exact-order", {}},
      {"color", "interval-sorted", {{"preintegration-size", "16"}}},
      {"color", "interval-sorted", {{"preintegration-size", "64"}}, false},
  };
  if (quick) std::erase_if(all, [](const BenchConfig& c) { return !c.in_quick; });
  return all;
}

std::string settings_label(const BenchConfig& c) {
  std::string s;
  for (const auto& [k, v] : c.options) s += (s.empty() ? "" : " ") + k + "=" + v;
  return s.empty() ? "default" : s;
}

struct Measurement {
  std::string dataset;
  size_t cells = 0;
  std::string quantity, mode, settings, ordering;
  uint32_t width = 0, height = 0, frames = 0;
  double gpu_median = 0, gpu_min = 0, gpu_max = 0;
  std::string passes;  // name=median ms, in order
  reference::ImageError error;
  double ssim = 0;  // mean structural similarity to the reference (same channels and peak as error)
  double reference_ms = 0;
  double peak = 1.0;  // the PSNR's peak
  bool pareto = false;
};

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

// Within each dataset and quantity (errors of different quantities are not comparable), a row is
// Pareto-optimal when no other row is at least as fast and at least as accurate, and better in one.
void mark_pareto(std::vector<Measurement>& rows) {
  for (auto& r : rows) {
    r.pareto = std::none_of(rows.begin(), rows.end(), [&](const Measurement& o) {
      if (&o == &r || o.dataset != r.dataset || o.quantity != r.quantity) return false;
      const bool no_worse = o.gpu_median <= r.gpu_median && o.error.rmse <= r.error.rmse;
      const bool better = o.gpu_median < r.gpu_median || o.error.rmse < r.error.rmse;
      return no_worse && better;
    });
  }
}

void write_csv(const std::filesystem::path& path, const std::vector<Measurement>& rows) {
  std::ofstream out(path);
  out << "dataset,cells,quantity,mode,settings,ordering,width,height,frames,gpu_ms_median,gpu_ms_min,gpu_ms_max,"
         "passes,rmse,max_abs,psnr_db,ssim,peak,non_finite,reference_ms,pareto\n";
  for (const auto& r : rows)
    out << '"' << r.dataset << "\"," << r.cells << ',' << r.quantity << ',' << r.mode << ',' << r.settings << ",\""
        << r.ordering << "\"," << r.width << ',' << r.height << ',' << r.frames << ',' << json_number(r.gpu_median) << ','
        << json_number(r.gpu_min) << ',' << json_number(r.gpu_max) << ",\"" << r.passes << "\"," << json_number(r.error.rmse)
        << ',' << json_number(r.error.max_abs) << ',' << (std::isinf(r.error.psnr_db) ? "inf" : json_number(r.error.psnr_db))
        << ',' << json_number(r.ssim) << ',' << json_number(r.peak) << ',' << r.error.non_finite << ',' << json_number(r.reference_ms) << ',' << (r.pareto ? 1 : 0) << '\n';
  if (!out) throw InputError(path.string(), "cannot write the CSV");
}

std::string fixed(double v, int digits) {
  if (std::isinf(v)) return "inf";
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

void write_report(const std::filesystem::path& path, const std::vector<Measurement>& rows, const std::string& device,
                  const std::string& driver, const std::string& command) {
  std::ofstream out(path);
  out << "# prismoid bench\n\n- device: " << device << "\n- driver: " << driver << "\n- command: `" << command << "`\n"
      << "- error: against the CPU double-precision reference; optical depth and transmittance compare the quantity\n"
      << "  (PSNR peak: the reference's largest optical depth, or 1), color the display RGB (peak 1); SSIM: mean\n"
      << "  structural similarity (Wang et al. 2004, 11x11 Gaussian window) on the same channels and peak\n"
      << "- `*`: Pareto-optimal within its quantity (no other row is both at least as fast and at least as accurate)\n";
  std::vector<std::string> datasets;
  for (const auto& r : rows)
    if (std::find(datasets.begin(), datasets.end(), r.dataset) == datasets.end()) datasets.push_back(r.dataset);
  for (const auto& d : datasets) {
    std::vector<const Measurement*> sorted;
    for (const auto& r : rows)
      if (r.dataset == d) sorted.push_back(&r);
    std::stable_sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) { return a->gpu_median < b->gpu_median; });
    const Measurement& f = *sorted.front();
    out << "\n## " << d << " (" << f.cells << " cells, " << f.width << "x" << f.height << ", " << f.frames << " frames)\n\n"
        << "| | quantity | mode | settings | GPU ms (median) | min-max | RMSE | max abs | PSNR dB | SSIM | reference ms |\n"
        << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto* r : sorted)
      out << "| " << (r->pareto ? "*" : "") << " | " << r->quantity << " | " << r->mode << " | " << r->settings << " | "
          << fixed(r->gpu_median, 4) << " | " << fixed(r->gpu_min, 4) << "-" << fixed(r->gpu_max, 4) << " | "
          << fixed(r->error.rmse, 3) << " | " << fixed(r->error.max_abs, 3) << " | " << fixed(r->error.psnr_db, 4) << " | "
          << fixed(r->ssim, 6) << " | " << fixed(r->reference_ms, 4) << (r->error.non_finite ? " | non-finite: " + std::to_string(r->error.non_finite) : "")
          << " |\n";
  }
  if (!out) throw InputError(path.string(), "cannot write the report");
}

}  // namespace

int cmd_bench(const std::vector<std::string>& args) {
  const std::vector<std::string> passed_through = {"density-scale", "tf", "tf-range", "array", "component", "background"};
  std::vector<std::string> value_options = {"out", "size", "frames", "device"};
  value_options.insert(value_options.end(), passed_through.begin(), passed_through.end());
  const ParsedArgs a = parse(args, 1, value_options, {"quick", "validate", "help"});
  if (a.flags.count("help")) { std::cout << kBenchHelp; return kOk; }
  if (!a.has("out")) throw InputError("bench", "--out DIR is required");
  const bool quick = a.flags.count("quick") > 0;
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : quick ? VkExtent2D{96, 72} : VkExtent2D{400, 300};
  const uint32_t frames = a.has("frames") ? parse_uint("frames", a.values.at("frames")) : quick ? 3 : 10;
  if (frames == 0 || frames > 10000) throw InputError("--frames", "must be between 1 and 10000");
  const std::filesystem::path out_dir = a.values.at("out");
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError(out_dir.string(), "cannot create the output folder: " + ec.message());

  const std::vector<std::string> datasets = a.files.empty() ? std::vector<std::string>{"", "ball:2"} : a.files;
  const std::vector<BenchConfig> configs = bench_configs(quick);

  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});

  std::vector<Measurement> rows;
  for (const std::string& file : datasets) {
    std::map<std::string, std::pair<frame::OffscreenFrame, double>> references;  // by quantity: image, CPU ms
    for (const BenchConfig& config : configs) {
      ParsedArgs one;
      if (!file.empty()) one.files.push_back(file);
      for (const auto& o : passed_through)
        if (a.has(o)) one.values[o] = a.values.at(o);
      one.values["quantity"] = config.quantity;
      one.values["mode"] = config.mode;
      for (const auto& [k, v] : config.options) one.values[k] = v;
      std::optional<VolumeChoice> chosen;
      try {
        chosen = volume_choice(one);
      } catch (const InputError& e) {
        // A dataset without a scalar array has no colour; its other quantities are still measured.
        if (config.quantity != "color") throw;
        std::cerr << "prismoid: bench: skipping color " << config.mode << " " << settings_label(config) << ": " << e.what() << "\n";
        continue;
      }
      const VolumeChoice& choice = *chosen;
      const Camera camera = camera_from(one, bounds_of(choice.mesh));
      const volume::ResolveSettings& resolve = choice.settings.resolve;

      auto ref = references.find(config.quantity);
      if (ref == references.end()) {
        const auto start = std::chrono::steady_clock::now();
        frame::OffscreenFrame image = field_of(one) ? render_field_reference(choice.mesh, camera, resolve, size)
                                                    : render_reference(choice.mesh, camera, resolve, size);
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        ref = references.emplace(config.quantity, std::make_pair(std::move(image), ms)).first;
      }

      frame::FrameRenderer renderer(device, choice.mesh);
      renderer.render_offscreen(camera, choice.settings, size);  // warm-up: caches, clocks, first-use work
      std::vector<std::vector<vk::PassTiming>> timings;
      std::vector<double> totals;
      frame::OffscreenFrame result;
      for (uint32_t i = 0; i < frames; ++i) {
        renderer.forget_history();  // each timed frame costs what a moving camera's does: no order reused
        result = renderer.render_offscreen(camera, choice.settings, size);
        double total = 0.0;
        for (const auto& p : result.passes) total += p.gpu_ms;
        totals.push_back(total);
        timings.push_back(result.passes);
      }

      Measurement m;
      m.dataset = choice.mesh.name;
      m.cells = choice.mesh.tets.size();
      m.quantity = config.quantity;
      m.mode = config.mode;
      m.settings = settings_label(config);
      m.ordering = result.report.ordering;
      m.width = size.width;
      m.height = size.height;
      m.frames = frames;
      m.gpu_median = median(totals);
      m.gpu_min = *std::min_element(totals.begin(), totals.end());
      m.gpu_max = *std::max_element(totals.begin(), totals.end());
      m.passes = pass_medians(timings);
      m.error = error_of(result, ref->second.first, choice.quantity);
      m.ssim = ssim_of(result, ref->second.first, choice.quantity);
      m.reference_ms = ref->second.second;
      m.peak = peak_of(ref->second.first, choice.quantity);
      std::cout << m.dataset << " " << m.quantity << " " << m.mode << " " << m.settings << ": " << json_number(m.gpu_median)
                << " ms GPU, RMSE " << json_number(m.error.rmse) << "\n";
      rows.push_back(std::move(m));
    }
  }
  mark_pareto(rows);

  std::string command = "prismoid";
  for (const auto& s : args) command += " " + s;
  write_csv(out_dir / "bench.csv", rows);
  write_report(out_dir / "report.md", rows, caps.name, caps.driver_info, command);
  std::cout << "wrote " << (out_dir / "bench.csv").string() << " and " << (out_dir / "report.md").string() << "\n";
  return validation_exit(instance);
}

}  // namespace prismoid::app
