// `prismoid bench`: what accuracy costs in time. Every case (app/bench/bench_cases.hpp) is
// rendered on the GPU, timed over repeated frames after a warm-up, and measured against the CPU
// double-precision reference, which is computed once per dataset, quantity and image size and
// shared by every mode measured against it.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include <glm/geometric.hpp>
#include <unistd.h>

#include "app/bench/bench_cases.hpp"
#include "app/bench/bench_plot.hpp"
#include "app/bench/bench_table.hpp"
#include "app/bench/mixed_bench.hpp"
#include "app/bench/surface_bench.hpp"
#include "app/bench/vtk_peers.hpp"
#include "app/bench/x_display.hpp"
#include "app/cli.hpp"
#include "app/commands.hpp"
#include "app/common/backend_cache.hpp"
#include "app/common/cli_args.hpp"
#include "app/common/dataset_loader.hpp"
#include "app/common/output_files.hpp"
#include "app/common/volume_options.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/metrics/flip.hpp"
#include "renderer/metrics/image_error.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/timing/frame_timing.hpp"
#include "renderer/timing/warm_up.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/volume/cpu/reference_frame.hpp"
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
    "  --out DIR            folder for bench.csv and report.md (created if missing); one that holds\n"
    "                       either already is refused, unless --replace\n"
    "  --replace            replace the bench.csv, report.md and plots of an earlier run in DIR\n"
    "  --quick              96x72, 3 frames, one or two settings per sweep: a smoke test in a minute\n"
    "  --size WxH           image size (default 400x300)\n"
    "  --frames N           timed frames (default 10); times are the median, with the best and worst,\n"
    "                       and the SM clock meanwhile where nvidia-smi is on PATH\n"
    "  --warm-up SECONDS    frames drawn before each row's timed ones, for at least this long (default\n"
    "                       2, --quick 0: one frame); lets the GPU leave its idle clock\n"
    "  --sweeps LIST        comma-separated subset of: modes, tetlet-size, preintegration, time,\n"
    "                       image-size, march-step, cells, surfaces, mixed (default: all); mixed: the first dataset\n"
    "                       cut by an opaque square through its centre, in each GPU surface mode without\n"
    "                       indirect light on each volume backend, against the mixed scene's reference\n"
    "  --surfaces LIST      the surfaces sweep's scenes: cornell-box, furnace:A or surface files\n"
    "                       (default cornell-box); every surface mode the device draws, against the\n"
    "                       CPU reference of what the mode computes, 4x4 supersampled\n"
    "  --surface-modes LIST the surfaces sweep's modes (default: every mode the device draws)\n"
    "  --shading-scales L   equal terms: also bench htex, texel, msa and fastatlas at these shading-rate\n"
    "                       factors SF (texels per pixel side; SF^2 of the samples), e.g. 0.5,0.25,0.125\n"
    "  --fastatlas-atlases L  fastatlas rows at these atlas sides (e.g. 2048,4096,8192)\n"
    "  --fastatlas-refresh L  with --surface-motion: fastatlas rows with temporal reuse refreshed every\n"
    "                       n frames (e.g. 10, the paper's)\n"
    "  --max-triangle-pixels P  split the surface scenes' triangles until none spans more than P pixels\n"
    "                       of the view (as the meshlet atlas's paper prepares its scenes; rows say refined=P)\n"
    "  --surface-shadows S  surface rows with shadows on, off or both (default both; off alone where\n"
    "                       the device traces no rays)\n"
    "  --shading-budget N   also bench htex, texel and msa at about N shaded samples per frame\n"
    "                       (equal terms), or at the scene's covered pixels with 'covered'\n"
    "  --surface-lights N   replace the surface scenes' lights by N shadow-casting point lights\n"
    "                       around them (shading load; texel shading's paper uses 30); the CPU\n"
    "                       reference is then not supersampled\n"
    "  --surface-still      also bench htex, texel and msa frames that reuse a still camera's shading\n"
    "  --surface-motion DEG also bench forward, htex, texel and msa with a camera that orbits DEG\n"
    "                       degrees per frame (ending at the scene's camera, where the error is taken)\n"
    "  --msa-charts LIST    the msa rows' meshlet charts, a set of rows each: projection (default),\n"
    "                       conformal (least-squares conformal maps)\n"
    "  --msa-amortize LIST  with --surface-motion: msa rows that shade every n-th frame (e.g. 4,8,16),\n"
    "                       showing from the atlas in between (the meshlet shading atlas's amortization)\n"
    "  --max-cells N        the cell-count sweep's largest mesh (default 2000000; the sweep splits\n"
    "                       field:marschner-lobb into N^3 cubes, 6 cells each, N = 6, 12, 24, 48, 96, 128)\n"
    "  --no-peers           leave out VTK's mappers (vtkProjectedTetrahedraMapper,\n"
    "                       vtkUnstructuredGridVolumeRayCastMapper, vtkUnstructuredGridVolumeZSweepMapper), which\n"
    "                       otherwise render each FILE once, timed by wall clock, on the same camera and transfer\n"
    "                       function (colour where the data has scalars, else transmittance)\n"
    "  --no-plots           leave out the PNG plots (error against time per dataset, quantity and size,\n"
    "                       Pareto front marked; time against cell count), drawn with VTK's charts\n"
    "                       VTK draws through X: without DISPLAY the bench starts a private Xvfb\n"
    "  --replot DIR         draw the plots of an earlier run's DIR/bench.csv (e.g. one made on a machine\n"
    "                       without X, with --no-plots) into DIR and link them from DIR/report.md\n"
    "  --device N           use Vulkan device N (see `prismoid devices`)\n"
    "  --validate           enable the Khronos validation layer; exit 4 if it reports anything\n"
    "  --density-scale S --tf PRESET|FILE --tf-range LO,HI --array NAME --component C --background R,G,B\n"
    "                       as for `prismoid render`, applied to every configuration of the FILEs\n"
    "\n"
    "Sweeps, per FILE: modes (optical depth and transmittance in mesh order; color with every GPU\n"
    "mode that does not march: mesh order, GPU-sorted, exact order), tetlet-size (1, 4, 8 beside the\n"
    "default 16), preintegration (table sizes 16, 64, 256 beside exact segments), time (a time series'\n"
    "every step: transmittance in mesh order, colour in exact order); on the first FILE:\n"
    "image-size (half and twice --size); on field:marschner-lobb: march-step (the GPU-sorted march at\n"
    "1/25 to 1/400 of the diagonal, beside its tetrahedra) and cells (N^3 cubes). Errors: RMSE, largest absolute error,\n"
    "PSNR and SSIM of the quantity (peak: the reference's largest optical depth, or 1 for\n"
    "transmittance) or of the display RGB (peak 1) for color; non-finite values are counted, never\n"
    "averaged. FILE: anything `prismoid render` reads (default: the embedded default dataset and ball:2).\n";

namespace {

double ssim_of(const frame::OffscreenFrame& gpu, const frame::OffscreenFrame& ref, volume::Quantity q) {
  if (q == volume::Quantity::Color) return reference::ssim(gpu.display, ref.display, ref.width, ref.height, 1.0, 4, 3);
  return reference::ssim(gpu.quantity, ref.quantity, ref.width, ref.height, frame::error_peak(ref, q), 1, 1);
}

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The mixed sweep's volume: `dataset` with the options passed through to each dataset, in colour
// in exact order (the caller falls back to transmittance where the data has no scalar array).
ParsedArgs mixed_volume_args(const ParsedArgs& a, const std::string& dataset, const std::vector<std::string>& passed_through) {
  ParsedArgs one;
  if (!dataset.empty()) one.files.push_back(dataset);
  for (const auto& o : passed_through)
    if (a.has(o)) one.values[o] = a.values.at(o);
  one.values["quantity"] = "color";
  one.values["mode"] = std::string(frame::find_volume_mode(frame::Ordering::Exact, false)->name);
  return one;
}

// Loads each dataset once per way of loading it (as extinction or as the transfer function's
// scalar; a .vdb as voxels or as marched regions) and hands out copies.
// The time step a case draws of a time series ("" for other datasets): meshes and references
// are kept per step.
std::string step_of(const ParsedArgs& a) {
  std::string step;
  for (const char* option : {"time-step", "time"})
    if (a.has(option)) step.append("|").append(option).append("=").append(a.values.at(option));
  return step;
}

class MeshCache {
 public:
  TetMesh operator()(const ParsedArgs& a, bool scalar_field) {
    std::string key = (a.files.empty() ? std::string() : a.files.front()) + (scalar_field ? "|scalar" : "|extinction") + step_of(a);
    if (samples_field(a)) key += "|march";
    auto it = meshes_.find(key);
    if (it == meshes_.end()) it = meshes_.emplace(key, load_scene(a, scalar_field)).first;
    return it->second;
  }
  void clear() { meshes_.clear(); }

 private:
  std::map<std::string, TetMesh> meshes_;
};

// A comma-separated option value; an empty list or item (`--sweeps ,`, `a,,b`) is refused: it
// once measured nothing and wrote a header-only CSV with exit 0.
std::vector<std::string> split_list(const std::string& option, const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  // getline drops one trailing empty item: "a," reads as {"a"}.
  if (out.empty() || s.back() == ',' || std::find(out.begin(), out.end(), "") != out.end())
    throw InputError("--" + option, "has an empty item in '" + s + "' (a list is NAME,NAME,...)");
  return out;
}

// A peer's transmittance recovered from its display, which mixes the medium colour and the
// background by T: display = medium (1 - T) + background T, inverted on the channel where the
// two differ most (the 8-bit framebuffer's steps grow by 1 / |background - medium| there).
std::vector<float> transmittance_of_display(const std::vector<float>& display, const volume::ResolveSettings& resolve) {
  int c = 0;
  for (int k = 1; k < 3; ++k)
    if (std::abs(resolve.background[k] - resolve.medium[k]) > std::abs(resolve.background[c] - resolve.medium[c])) c = k;
  const double m = resolve.medium[c], b = resolve.background[c];
  std::vector<float> t(display.size() / 4);
  for (size_t i = 0; i < t.size(); ++i) t[i] = float((double(display[4 * i + size_t(c)]) - m) / (b - m));
  return t;
}

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof(name) - 1) != 0) return {};
  return name;
}

// The plots beside report.md: error against time per dataset, quantity and size (every row), and
// time against cell count (the modes and cell-count sweeps, at the preset's size, each interval
// backend a line of its own).
void write_plots(const std::filesystem::path& dir, const std::vector<bench::BenchRow>& rows, bench::ReportContext& context, OutputFiles& files) {
  std::vector<bench::BenchPoint> all, scaling;
  for (const auto& r : rows) {
    bench::BenchPoint p{r.dataset, r.quantity, r.mode, r.settings == "default" ? "" : r.settings, r.cells, r.ms_median, r.error.rmse,
                        r.width, r.height};
    all.push_back(p);
    const bool backend_only = r.settings.rfind("volume-backend=", 0) == 0 && r.settings.find(' ') == std::string::npos;
    if ((r.sweep == "modes" || r.sweep == "cells") && (r.settings == "default" || backend_only)) scaling.push_back(p);
  }
  std::vector<std::pair<std::string, bench::PlotSpec>> plots;
  for (auto& plot : bench::bench_plots(all)) {
    size_t points = 0;  // a group of one row (a mesh of the cell sweep) has nothing to trade off
    for (const auto& series : plot.second.series) points += series.points.size();
    if (plot.first != "time_vs_cells.png" && points > 1) plots.push_back(std::move(plot));
  }
  for (auto& plot : bench::bench_plots(scaling))
    if (plot.first == "time_vs_cells.png") plots.push_back(std::move(plot));
  // Surface rows with a shading rate: FLIP against the samples shaded, a line per mode and
  // settings through its rates (sf=...; the mode's own rate is sf=1).
  std::vector<bench::RatePoint> rates;
  for (const auto& r : rows) {
    if (r.sweep != "surfaces" || !std::isfinite(r.flip) || r.shaded == 0) continue;
    std::string series = r.mode, label = "sf=1";
    std::istringstream words(r.settings);
    for (std::string w; words >> w;) {
      if (w.rfind("sf=", 0) == 0) label = w;
      else if (w.rfind("shadows=", 0) != 0) series += " " + w;
    }
    if (r.settings.find("shadows=on") != std::string::npos) series += " (shadows)";
    rates.push_back({r.dataset + " " + std::to_string(r.width) + "x" + std::to_string(r.height), series, label, double(r.shaded), r.flip});
  }
  for (auto& plot : bench::shading_rate_plots(rates)) plots.push_back(std::move(plot));
  for (const auto& [file, spec] : plots) {
    const std::string png = (dir / file).string();
    try {
      files.output(png, "--out", {".png"});
      files.write(png, [&](const std::string& temporary) { bench::write_plot_png(spec, temporary); });
      context.plots.emplace_back(spec.title, file);
    } catch (const std::exception& e) {
      files.discard(png);
      std::cerr << "prismoid: bench: plot " << file << ": " << e.what() << "\n";
      context.notes.push_back("plot " + file + " failed: " + e.what());
    }
  }
}

// --replot DIR: the plots of an earlier run, linked from its report.
int replot(const std::filesystem::path& dir) {
  const std::vector<bench::BenchRow> rows = bench::read_csv(dir / "bench.csv");
  if (rows.empty()) throw InputError((dir / "bench.csv").string(), "has no measurements to plot");
  const std::filesystem::path report_path = dir / "report.md";
  OutputFiles files;  // the plots and the report with their links, all or none
  files.input((dir / "bench.csv").string());
  files.output(report_path.string(), "--replot", {".md"});
  const bench::XDisplay x;
  bench::ReportContext context;
  write_plots(dir, rows, context, files);
  std::string report;
  {
    std::ifstream in(report_path);
    if (!in) throw InputError(report_path.string(), "cannot open the report to link the plots from");
    std::stringstream text;
    text << in.rdbuf();
    report = text.str();
  }
  std::string section = "\n## Plots\n\n";
  for (const auto& [title, file] : context.plots) section += "- [" + title + "](" + file + ")\n";
  for (const auto& note : context.notes) section += "- " + note + "\n";
  if (const size_t old = report.find("\n## Plots\n"); old != std::string::npos) {  // replace an earlier list
    const size_t end = report.find("\n## ", old + 1);
    report.erase(old, end == std::string::npos ? std::string::npos : end - old);
  }
  const size_t first = report.find("\n## ");
  report.insert(first == std::string::npos ? report.size() : first, section);
  files.write(report_path.string(), [&](const std::string& file) {
    std::ofstream out(file);
    out << report;
    out.close();
    if (!out) throw InputError(file, "cannot write the report");
  });
  files.commit();
  std::cout << "wrote " << context.plots.size() << " plots into " << dir.string() << " and linked them from " << report_path.string() << "\n";
  return kOk;
}

// Each light is a shadow ray per shaded sample and a term of the CPU reference's sum; 1e9 once
// ran out of memory.
constexpr uint32_t kMaxSurfaceLights = 4096;

// The surfaces sweep's options, all checked before any work (a typo once failed 18 s into
// --quick, hours into a full bench). Lists refuse empty items and names they do not know.
bench::SurfaceBenchOptions surface_options(const ParsedArgs& a) {
  bench::SurfaceBenchOptions so;
  if (a.has("surfaces")) so.scenes = split_list("surfaces", a.values.at("surfaces"));
  if (a.has("surface-modes")) so.modes = split_list("surface-modes", a.values.at("surface-modes"));
  for (const std::string& mode : so.modes) {
    const surface::SurfaceMode* m = surface::find_surface_mode(mode);
    if (m == nullptr || !m->gpu()) {
      std::string known;
      for (const surface::SurfaceMode& t : surface::surface_mode_table())
        if (t.gpu()) known += (known.empty() ? "" : ", ") + std::string(t.name);
      throw InputError("--surface-modes", "'" + mode + "' is not a GPU surface mode (" + known + ")");
    }
  }
  if (a.has("surface-lights")) {
    so.extra_lights = parse_uint("surface-lights", a.values.at("surface-lights"));
    if (so.extra_lights > kMaxSurfaceLights)
      throw InputError("--surface-lights", "at most " + std::to_string(kMaxSurfaceLights) + " lights, got " + std::to_string(so.extra_lights));
  }
  so.still_rows = a.flags.count("surface-still") > 0;
  if (a.has("surface-motion")) {
    so.motion_degrees = parse_double("surface-motion", a.values.at("surface-motion"));
    if (!(so.motion_degrees > 0.0 && so.motion_degrees <= 45.0))
      throw InputError("--surface-motion", "degrees per frame must lie in (0, 45]");
  }
  if (a.has("msa-charts")) {
    so.msa_charts.clear();
    for (const std::string& kind : split_list("msa-charts", a.values.at("msa-charts"))) {
      msa::Parametrization p;
      if (!msa::parse_parametrization(kind, p))
        throw InputError("--msa-charts", "must list projection, conformal, perspective or orthographic, got '" + kind + "'");
      so.msa_charts.push_back(p);
    }
  }
  if (a.has("msa-amortize")) {
    if (!a.has("surface-motion")) throw InputError("--msa-amortize", "needs --surface-motion (amortization matters while the camera moves)");
    for (const std::string& n : split_list("msa-amortize", a.values.at("msa-amortize"))) {
      const uint32_t every = parse_uint("msa-amortize", n);
      if (every < 2) throw InputError("--msa-amortize", "each n must be at least 2 (1 shades every frame: the moving msa row)");
      so.msa_amortization.push_back(every);
    }
  }
  if (a.has("fastatlas-refresh")) {
    if (!a.has("surface-motion")) throw InputError("--fastatlas-refresh", "needs --surface-motion (temporal reuse matters while the camera moves)");
    for (const std::string& n : split_list("fastatlas-refresh", a.values.at("fastatlas-refresh"))) {
      const uint32_t every = parse_uint("fastatlas-refresh", n);
      if (every < 2 || every > 1000) throw InputError("--fastatlas-refresh", "each n must lie in [2, 1000] (1 refreshes every frame: the moving row)");
      so.fastatlas_refresh.push_back(every);
    }
  }
  if (a.has("max-triangle-pixels")) {
    so.max_triangle_pixels = parse_double("max-triangle-pixels", a.values.at("max-triangle-pixels"));
    if (!(so.max_triangle_pixels > 0.0) || !std::isfinite(so.max_triangle_pixels))
      throw InputError("--max-triangle-pixels", "must be a finite, positive number of pixels");
  }
  if (a.has("surface-shadows")) {
    const std::string v = a.values.at("surface-shadows");
    if (v != "on" && v != "off" && v != "both") throw InputError("--surface-shadows", "must be on, off or both, got '" + v + "'");
    so.shadows_on = v != "off";
    so.shadows_off = v != "on";
  }
  if (a.has("shading-scales"))
    for (const std::string& v : split_list("shading-scales", a.values.at("shading-scales"))) {
      const double sf = parse_double("shading-scales", v);
      if (!(sf > 0.0 && sf <= 1.0)) throw InputError("--shading-scales", "each SF must lie in (0, 1], got '" + v + "'");
      so.shading_scales.push_back(sf);
    }
  if (a.has("fastatlas-atlases"))
    for (const std::string& v : split_list("fastatlas-atlases", a.values.at("fastatlas-atlases"))) {
      const uint32_t side = parse_uint("fastatlas-atlases", v);
      if (side < 64 || side > 16384 || (side & (side - 1)) != 0)
        throw InputError("--fastatlas-atlases", "each atlas side must be a power of two from 64 to 16384, got '" + v + "'");
      so.fastatlas_atlases.push_back(side);
    }
  if (so.extra_lights > 0) so.supersample = 1;  // the CPU reference's cost grows with the lights: one sample per pixel
  if (a.has("shading-budget"))
    so.shading_budget = a.values.at("shading-budget") == "covered" ? bench::SurfaceBenchOptions::kBudgetCoveredPixels
                                                                    : parse_uint("shading-budget", a.values.at("shading-budget"));
  return so;
}

// The row's error columns: `image` against the reference `ref` (its image and CPU time).
void set_error(bench::BenchRow& m, const frame::OffscreenFrame& image, const std::pair<frame::OffscreenFrame, double>& ref,
               volume::Quantity quantity, VkExtent2D extent) {
  m.error = frame::frame_error(image, ref.first, quantity);
  m.ssim = ssim_of(image, ref.first, quantity);
  m.reference_ms = ref.second;
  m.peak = frame::error_peak(ref.first, quantity);
  if (quantity == volume::Quantity::Color) m.flip = reference::flip(image.display, ref.first.display, extent.width, extent.height, 4).mean;
}

// One volume case's row: drawn through the renderer facade as `render` draws (the timed frames,
// each a moving camera's, no image read back; then the image whose error is measured, one more
// frame of the same camera), measured against `ref` (the reference image and its CPU time).
bench::BenchRow volume_row(const vk::Device& device, const bench::BenchCase& c, const VolumeChoice& choice, bool analytic_field,
                           const Camera& camera, const std::pair<frame::OffscreenFrame, double>& ref, uint32_t frames,
                           double warm_up_seconds) {
  const VkExtent2D extent{c.size.width, c.size.height};
  mixed::SceneRenderer renderer({.volume = &choice.mesh, .analytic_field = analytic_field}, device, resolve_auto_backend);
  mixed::SceneSettings scene_settings;
  scene_settings.size = extent;
  scene_settings.volume_mode = choice.mode;
  scene_settings.volume = choice.settings;
  scene_settings.volume_backend_auto = choice.backend_auto;
  scene_settings.frames = frames;
  scene_settings.warm_up_seconds = warm_up_seconds;
  const mixed::SceneFrame drawn = renderer.render(camera, scene_settings);
  const frame::OffscreenFrame& result = *drawn.volume;
  const timing::FrameTiming& timing = *drawn.timing;

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
  bench::set_times(m, timing);
  m.cpu_ms = timing::median_of(drawn.frame_cpu_ms);
  m.mesh_bytes = result.report.mesh_bytes;
  // The image is one more frame's: every frame draws the same cells from the same camera.
  set_error(m, result, ref, choice.quantity, extent);
  std::cout << m.dataset << " " << m.sweep << " " << m.quantity << " " << m.mode << " " << m.settings << " " << m.width << "x"
            << m.height << ": " << json_number(m.ms_median) << " ms GPU, RMSE " << json_number(m.error.rmse) << std::endl;
  return m;
}

// By dataset, step, quantity and size: a reference image and its CPU time.
using References = std::map<std::string, std::pair<frame::OffscreenFrame, double>>;

const std::pair<frame::OffscreenFrame, double>& reference_for(References& references, const ParsedArgs& one, const std::string& quantity,
                                                              const VolumeChoice& choice, const Camera& camera, VkExtent2D extent) {
  const std::string key = (one.files.empty() ? std::string() : one.files.front()) + step_of(one) + "|" + quantity + "|" +
                          std::to_string(extent.width) + "x" + std::to_string(extent.height);
  auto ref = references.find(key);
  if (ref == references.end()) {
    const auto start = std::chrono::steady_clock::now();
    frame::OffscreenFrame image = frame::reference_of(choice.mesh, camera, choice.settings.resolve, extent, field_of(one).has_value());
    ref = references.emplace(key, std::make_pair(std::move(image), ms_since(start))).first;
  }
  return ref->second;
}

// A `time` case of step switches (bench::kStepSwitch): a viewer at a still camera moving through
// every step, one interactive frame each (as the window and the plugin draw them), timed on the
// wall clock from the step's mesh in memory to its image read back. `fields_only`: after the
// first step only the fields go to the GPU (SceneRenderer::set_volume: a static mesh's order is
// kept); else each step is uploaded whole. The first round through the steps warms up; the
// switches of the `frames` rounds after it are timed (the first step of each round, which has no
// step before it, is not). The error is the worst step's, against that step's reference.
std::optional<bench::BenchRow> step_switch_row(const vk::Device& device, const bench::BenchCase& c, const ParsedArgs& one, bool fields_only,
                                               MeshCache& meshes, References& references, uint32_t frames) {
  const size_t n = bench::time_steps_of(c.dataset);
  std::vector<VolumeChoice> steps;
  std::vector<ParsedArgs> step_args;
  for (size_t i = 0; i < n; ++i) {
    ParsedArgs si = one;
    si.values["time-step"] = std::to_string(i);
    try {
      steps.push_back(volume_choice(si, std::ref(meshes)));
    } catch (const InputError& e) {
      if (c.quantity != "color") throw;
      std::cerr << "prismoid: bench: skipping the step switches of " << c.dataset << ": " << e.what() << "\n";
      return std::nullopt;
    }
    step_args.push_back(si);
  }
  const Camera camera = camera_from(one, bounds_of(steps.front().mesh));
  const VkExtent2D extent{c.size.width, c.size.height};
  std::vector<double> ms;
  std::vector<frame::OffscreenFrame> images(n);
  mixed::VolumeUploads uploads;
  for (uint32_t round = 0; round <= frames; ++round) {
    std::unique_ptr<mixed::SceneRenderer> kept;  // fields_only: the one renderer of the round
    for (size_t i = 0; i < n; ++i) {
      mixed::SceneSettings settings;
      settings.size = extent;
      settings.volume_mode = steps[i].mode;
      settings.volume = steps[i].settings;
      settings.interactive = true;
      const auto start = std::chrono::steady_clock::now();
      std::unique_ptr<mixed::SceneRenderer> fresh;
      if (kept) kept->set_volume(steps[i].mesh);
      else fresh = std::make_unique<mixed::SceneRenderer>(mixed::SceneData{.volume = &steps[i].mesh}, device);
      mixed::SceneRenderer& renderer = kept ? *kept : *fresh;
      mixed::SceneFrame f = renderer.render(camera, settings);
      if (round > 0 && i > 0) ms.push_back(ms_since(start));
      images[i] = std::move(*f.volume);
      uploads = renderer.volume_uploads();
      if (fields_only && !kept) kept = std::move(fresh);
    }
  }
  bench::BenchRow m;
  m.dataset = c.dataset + " (" + std::to_string(n) + " steps)";
  m.cells = steps.front().mesh.tets.size();
  m.sweep = c.sweep;
  m.quantity = c.quantity;
  m.mode = c.mode;
  m.settings = bench::settings_label(c);
  m.ordering = images.back().report.ordering;
  m.timer = "wall";
  m.width = extent.width;
  m.height = extent.height;
  m.frames = uint32_t(ms.size());
  m.ms_median = timing::median_of(ms);
  m.ms_min = *std::min_element(ms.begin(), ms.end());
  m.ms_max = *std::max_element(ms.begin(), ms.end());
  m.mesh_bytes = images.back().report.mesh_bytes;
  for (size_t i = 0; i < n; ++i) {
    const auto& ref = reference_for(references, step_args[i], c.quantity, steps[i], camera, extent);
    if (i > 0 && !(frame::frame_error(images[i], ref.first, steps[i].quantity).rmse > m.error.rmse)) continue;
    set_error(m, images[i], ref, steps[i].quantity, extent);
  }
  std::cout << m.dataset << " " << m.sweep << " " << m.settings << " " << m.width << "x" << m.height << ": "
            << json_number(m.ms_median) << " ms a step switch (wall; the last round's uploads: " << uploads.meshes
            << (uploads.meshes == 1 ? " mesh, " : " meshes, ") << uploads.fields << " field sets), worst RMSE "
            << json_number(m.error.rmse) << std::endl;
  return m;
}

// VTK's mappers' rows beside the volume row `m` (same mesh, camera and transfer function),
// measured against the same reference; a mapper that fails is left out with a note.
void add_peer_rows(std::vector<bench::BenchRow>& rows, bench::ReportContext& context, const bench::BenchRow& m, const VolumeChoice& choice,
                   const Camera& camera, const frame::OffscreenFrame& r, uint32_t frames) {
  const volume::ResolveSettings& resolve = choice.settings.resolve;
  for (const bench::Peer peer : bench::kPeers) {
    bench::BenchRow p = m;
    p.mode = std::string(bench::peer_name(peer));
    p.settings = "default";
    p.ordering = "VTK's own";
    p.timer = "wall";
    p.cpu_ms = 0;
    p.passes.clear();
    p.mesh_bytes = 0;
    p.flip = std::numeric_limits<double>::quiet_NaN();
    p.sm_mhz_min = p.sm_mhz_median = p.sm_mhz_max = std::numeric_limits<double>::quiet_NaN();  // the GPU row's, not VTK's
    try {
      const bench::PeerFrame f = bench::render_peer(peer, choice.mesh, camera, resolve, m.width, m.height, frames);
      const timing::Spread wall = timing::spread_of(f.frame_ms);
      p.ms_median = wall.median;
      p.ms_min = wall.best;
      p.ms_max = wall.worst;
      if (choice.quantity == volume::Quantity::Color) {
        p.error = reference::image_error(f.display, r.display, 1.0, 4, 3);
        p.ssim = reference::ssim(f.display, r.display, r.width, r.height, 1.0, 4, 3);
        p.flip = reference::flip(f.display, r.display, r.width, r.height, 4).mean;
      } else {
        const std::vector<float> t = transmittance_of_display(f.display, resolve);
        p.error = reference::image_error(t, r.quantity, 1.0, 1, 1);
        p.ssim = reference::ssim(t, r.quantity, r.width, r.height, 1.0, 1, 1);
      }
      if (context.notes.end() == std::find_if(context.notes.begin(), context.notes.end(), [](const std::string& n) { return n.rfind("VTK", 0) == 0; }))
        context.notes.push_back("VTK's mappers drew with OpenGL on " + f.gl_renderer +
                                "; their transmittance is read back from the 8-bit display (medium colour over the background)");
    } catch (const std::exception& e) {
      std::cerr << "prismoid: bench: " << p.mode << " on " << p.dataset << ": " << e.what() << "\n";
      context.notes.push_back(p.mode + " on " + p.dataset + " failed: " + e.what());
      continue;
    }
    std::cout << p.dataset << " " << p.quantity << " " << p.mode << ": " << json_number(p.ms_median) << " ms wall, RMSE "
              << json_number(p.error.rmse) << std::endl;
    rows.push_back(std::move(p));
  }
}

}  // namespace

int cmd_bench(const std::vector<std::string>& args) {
  const std::vector<std::string> passed_through = {"density-scale", "tf", "tf-range", "array", "component", "background"};
  std::vector<std::string> value_options = {"out", "size", "frames", "device", "sweeps", "max-cells", "replot", "surfaces", "surface-modes", "shading-budget",
                                            "warm-up", "surface-lights", "surface-motion", "msa-amortize", "msa-charts",
                                            "shading-scales", "fastatlas-atlases", "surface-shadows", "fastatlas-refresh",
                                            "max-triangle-pixels"};
  value_options.insert(value_options.end(), passed_through.begin(), passed_through.end());
  const ParsedArgs a = parse(args, 1, value_options, {"quick", "validate", "help", "no-peers", "no-plots", "surface-still", "replace"});
  if (a.flags.count("help")) { std::cout << kBenchHelp; return kOk; }
  if (a.has("replot")) {
    if (!a.files.empty() || a.values.size() > 1) throw InputError("--replot", "takes only the folder of an earlier run");
    return replot(a.values.at("replot"));
  }
  if (!a.has("out")) throw InputError("bench", "--out DIR is required");
  bench::BenchPreset preset;
  preset.quick = a.flags.count("quick") > 0;
  const VkExtent2D size = a.has("size") ? parse_size(a.values.at("size")) : preset.quick ? VkExtent2D{96, 72} : VkExtent2D{400, 300};
  preset.size = {size.width, size.height};
  preset.max_cells = a.has("max-cells") ? parse_uint("max-cells", a.values.at("max-cells")) : 2'000'000;
  const uint32_t frames = a.has("frames") ? parse_uint("frames", a.values.at("frames")) : preset.quick ? 3 : 10;
  if (frames == 0 || frames > 10000) throw InputError("--frames", "must be between 1 and 10000");
  preset.warm_up_seconds = a.has("warm-up") ? parse_double("warm-up", a.values.at("warm-up")) : preset.quick ? 0.0 : timing::kTimedWarmUpSeconds;
  if (!(preset.warm_up_seconds >= 0.0 && preset.warm_up_seconds <= 600.0)) throw InputError("--warm-up", "seconds must lie in [0, 600]");
  const std::vector<std::string> all_sweeps = {"modes", "tetlet-size", "preintegration", "time", "image-size", "march-step", "cells", "surfaces", "mixed"};
  const std::vector<std::string> sweeps = a.has("sweeps") ? split_list("sweeps", a.values.at("sweeps")) : all_sweeps;
  for (const auto& s : sweeps)
    if (std::find(all_sweeps.begin(), all_sweeps.end(), s) == all_sweeps.end())
      throw InputError("--sweeps", "unknown sweep '" + s + "' (modes, tetlet-size, preintegration, time, image-size, march-step, cells, surfaces, mixed)");
  bench::SurfaceBenchOptions so = surface_options(a);  // checked now, used by the surfaces sweep
  // Declared before the work: a folder made here goes again if the bench fails (or is stopped).
  const std::filesystem::path out_dir = a.values.at("out");
  OutputFiles files;
  for (const std::string& file : a.files) files.input(file);
  if (a.has("tf")) files.input(a.values.at("tf"));
  if (a.has("surfaces"))
    for (const std::string& scene : split_list("surfaces", a.values.at("surfaces"))) files.input(scene);
  files.folder(out_dir.string(), "--out");
  const std::string csv_path = (out_dir / "bench.csv").string(), report_path = (out_dir / "report.md").string();
  // An earlier run's results (docs/ holds committed ones) are replaced only when asked to.
  std::error_code ec;
  if (!a.flags.count("replace"))
    for (const std::string& earlier : {csv_path, report_path})
      if (std::filesystem::exists(earlier, ec))
        throw InputError(earlier, "exists: bench does not replace an earlier run's results; choose another --out, or add --replace");
  files.output(csv_path, "--out", {".csv"});
  files.output(report_path, "--out", {".md"});

  const std::vector<std::string> datasets = a.files.empty() ? std::vector<std::string>{"", "ball:2"} : a.files;
  std::vector<bench::BenchCase> cases = bench::bench_cases(datasets, preset);
  std::erase_if(cases, [&](const bench::BenchCase& c) { return std::find(sweeps.begin(), sweeps.end(), c.sweep) == sweeps.end(); });

  vk::Instance instance(vk::InstanceOptions{.validation = a.flags.count("validate") > 0});
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, parse_device(a));
  vk::Device device(instance, caps, {});

  // VTK draws the peers and the plots through X; one display for the whole run.
  const bool want_peers = !a.flags.count("no-peers"), want_plots = !a.flags.count("no-plots");
  std::optional<bench::XDisplay> x;
  std::string x_problem;
  if (want_peers || want_plots) try {
      x.emplace();
    } catch (const std::exception& e) {
      x_problem = e.what();
      std::cerr << "prismoid: bench: no X display for VTK's mappers and charts: " << x_problem << "\n";
    }
  bench::ReportContext context;
  context.notes.push_back("warm-up: each row's timed frames follow " +
                          (preset.warm_up_seconds > 0.0 ? "at least " + json_number(preset.warm_up_seconds) +
                                                              " s of its frames, more while they still got faster (at most 4x that)"
                                                        : std::string("one frame")) +
                          " (--warm-up), so the GPU has left its idle clock");
  if (!x_problem.empty()) context.notes.push_back("VTK's mappers and the plots were left out: no X display (" + x_problem + ")");

  MeshCache meshes;
  References references;
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
    if (const auto how = one.values.find(bench::kStepSwitch); how != one.values.end()) {
      const bool fields_only = how->second == "fields";
      one.values.erase(how);
      if (auto row = step_switch_row(device, c, one, fields_only, meshes, references, frames)) rows.push_back(std::move(*row));
      continue;
    }
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
    const VkExtent2D extent{c.size.width, c.size.height};
    const auto& ref = reference_for(references, one, c.quantity, choice, camera, extent);
    const bench::BenchRow m = volume_row(device, c, choice, field_of(one).has_value(), camera, ref, frames, preset.warm_up_seconds);

    // VTK's mappers on the same mesh, camera and transfer function: once per dataset the user
    // named, beside the exact-order colour, or beside transmittance where the data has no colour.
    const bool scalars = !choice.mesh.point_scalars.empty() || !choice.mesh.cell_scalars.empty();
    const bool exact_order = choice.mode->ordering == frame::Ordering::Exact && !choice.mode->march;
    // (Once: beside the mesh-shader backend's row; the compute backend's row of the same case
    // stands beside the same peers.)
    const bool peer_case = c.sweep == "modes" && user_file && choice.settings.backend == frame::IntervalBackend::Mesh &&
                           ((c.quantity == "color" && exact_order) || (c.quantity == "transmittance" && !scalars));
    if (peer_case && want_peers && x) add_peer_rows(rows, context, m, choice, camera, ref.first, frames);
    rows.push_back(m);
  }
  if (std::find(sweeps.begin(), sweeps.end(), "mixed") != sweeps.end()) {
    ParsedArgs one = mixed_volume_args(a, datasets.front(), passed_through);
    std::optional<VolumeChoice> chosen;
    try {
      chosen = volume_choice(one, std::ref(meshes));
    } catch (const InputError&) {  // no scalar array: no colour
      one.values["quantity"] = "transmittance";
      one.values.erase("mode");
      chosen = volume_choice(one, std::ref(meshes));
    }
    for (auto& row : bench::bench_mixed(device, *chosen, camera_from(one, bounds_of(chosen->mesh)),
                                        {preset.size.width, preset.size.height, frames, preset.warm_up_seconds}))
      rows.push_back(std::move(row));
  }
  if (std::find(sweeps.begin(), sweeps.end(), "surfaces") != sweeps.end()) {
    so.size = preset.size;
    so.frames = frames;
    so.warm_up_seconds = preset.warm_up_seconds;
    for (auto& row : bench::bench_surfaces(device, so)) rows.push_back(std::move(row));
    context.notes.push_back("surface rows are measured against " + bench::surface_reference_kind("") + ", " +
                            std::to_string(so.supersample) + "x" + std::to_string(so.supersample) + " supersampled");
  }
  bench::mark_pareto(rows);

  context.device = caps.name;
  context.driver = caps.driver_info;
  context.host = host_name();
  context.command = "prismoid";
  for (const auto& s : args)  // as a shell would need it: empty or spaced arguments quoted
    context.command += " " + (s.empty() || s.find_first_of(" \t'") != std::string::npos ? "\"" + s + "\"" : s);
  if (want_plots && x) write_plots(out_dir, rows, context, files);
  files.write(csv_path, [&](const std::string& file) { bench::write_csv(file, rows); });
  files.write(report_path, [&](const std::string& file) { bench::write_report(file, rows, context); });
  files.commit();
  std::cout << "wrote " << csv_path << " and " << report_path << "\n";
  return validation_exit(instance);
}

}  // namespace prismoid::app
