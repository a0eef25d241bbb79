#include "app/bench/bench_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "app/bench/pareto.hpp"
#include "app/common/cli_args.hpp"
#include "scene/input_error.hpp"

namespace prismoid::bench {

namespace {

bool comparable(const BenchRow& a, const BenchRow& b) {
  // A mixed row's error is of the volume over its surfaces, against another reference.
  return a.dataset == b.dataset && a.quantity == b.quantity && a.width == b.width && a.height == b.height &&
         (a.sweep == "mixed") == (b.sweep == "mixed");
}

std::string fixed(double v, int digits) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return "inf";
  std::ostringstream s;
  s << std::setprecision(digits) << v;
  return s.str();
}

std::string number(double v) { return std::isinf(v) && v > 0 ? "inf" : app::json_number(v); }

std::string mib(uint64_t bytes) { return fixed(double(bytes) / (1024.0 * 1024.0), 3); }

// What the measurements say, in words: per dataset, quantity and size with more than one row,
// the Pareto front from fastest to most accurate, and what each step along it costs and buys.
void write_findings(std::ostream& out, const std::vector<BenchRow>& rows) {
  std::vector<std::vector<const BenchRow*>> groups;
  for (const auto& r : rows) {
    auto group = std::find_if(groups.begin(), groups.end(), [&](const auto& members) { return comparable(*members.front(), r); });
    if (group == groups.end()) groups.push_back({&r});
    else group->push_back(&r);
  }
  bool any = false;
  for (auto& g : groups) {
    if (g.size() < 2) continue;
    std::vector<const BenchRow*> front;
    for (const auto* r : g)
      if (r->pareto) front.push_back(r);
    if (front.empty()) continue;
    std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->ms_median < b->ms_median; });
    if (!any) out << "\n## What the measurements say\n\n";
    any = true;
    const auto name = [](const BenchRow* r) {
      return r->mode + (r->settings == "default" ? std::string() : " (" + r->settings + ")");
    };
    out << "- **" << g.front()->dataset << ", " << g.front()->quantity << ", " << g.front()->width << "x" << g.front()->height
        << "** (" << g.size() << " rows): ";
    if (front.size() == 1) {
      out << name(front[0]) << " is both the fastest and the most accurate (" << fixed(front[0]->ms_median, 3) << " ms, RMSE "
          << fixed(front[0]->error.rmse, 3) << ").\n";
      continue;
    }
    out << "the Pareto front runs from " << name(front.front()) << " (" << fixed(front.front()->ms_median, 3) << " ms, RMSE "
        << fixed(front.front()->error.rmse, 3) << ")";
    for (size_t i = 1; i < front.size(); ++i) {
      const double time = front[i]->ms_median / front[i - 1]->ms_median;
      const double error = front[i - 1]->error.rmse / front[i]->error.rmse;
      out << (i + 1 == front.size() ? " and " : ", ") << name(front[i]) << " (" << fixed(front[i]->ms_median, 3) << " ms, RMSE "
          << fixed(front[i]->error.rmse, 3) << ": " << fixed(time, 3) << "x the time for " << fixed(error, 3) << "x less error)";
    }
    const size_t dominated = g.size() - front.size();
    out << "; " << dominated << (dominated == 1 ? " row is" : " rows are") << " dominated.\n";
  }
}

}  // namespace

void set_times(BenchRow& row, const timing::FrameTiming& timing) {
  row.frames = timing.frames;
  row.ms_median = timing.total_ms.median;
  row.ms_min = timing.total_ms.best;
  row.ms_max = timing.total_ms.worst;
  row.passes.clear();
  for (const timing::PassSpread& p : timing.passes) row.passes += (row.passes.empty() ? "" : ";") + p.name + "=" + app::json_number(p.ms.median);
  if (timing.sm_clock) {
    row.sm_mhz_min = timing.sm_clock->min_mhz;
    row.sm_mhz_median = timing.sm_clock->median_mhz;
    row.sm_mhz_max = timing.sm_clock->max_mhz;
  }
}

void mark_pareto(std::vector<BenchRow>& rows) {
  std::vector<bool> done(rows.size(), false);
  for (size_t i = 0; i < rows.size(); ++i) {
    if (done[i]) continue;
    std::vector<size_t> group;  // the rows comparable with row i
    std::vector<TimeError> points;
    for (size_t j = i; j < rows.size(); ++j)
      if (!done[j] && comparable(rows[i], rows[j])) {
        done[j] = true;
        group.push_back(j);
        // A row with a non-finite pixel has an error of no meaning: never optimal, never dominating.
        const double error = rows[j].error.non_finite ? std::numeric_limits<double>::quiet_NaN() : rows[j].error.rmse;
        points.push_back({rows[j].ms_median, error});
      }
    const std::vector<bool> optimal = pareto_optimal(points);
    for (size_t k = 0; k < group.size(); ++k) rows[group[k]].pareto = optimal[k];
  }
}

void write_csv(const std::filesystem::path& path, const std::vector<BenchRow>& rows) {
  std::ofstream out(path);
  out << "dataset,cells,sweep,quantity,mode,settings,ordering,timer,width,height,frames,ms_median,ms_min,ms_max,cpu_ms,"
         "passes,mesh_bytes,rmse,max_abs,psnr_db,ssim,flip_mean,peak,non_finite,reference_ms,pareto,shaded,mode_bytes,"
         "sm_mhz_min,sm_mhz_median,sm_mhz_max,space\n";
  const auto optional_number = [](double v) { return std::isnan(v) ? std::string() : number(v); };
  for (const auto& r : rows)
    out << '"' << r.dataset << "\"," << r.cells << ',' << r.sweep << ',' << r.quantity << ',' << r.mode << ",\"" << r.settings
        << "\",\"" << r.ordering << "\"," << r.timer << ',' << r.width << ',' << r.height << ',' << r.frames << ','
        << number(r.ms_median) << ',' << number(r.ms_min) << ',' << number(r.ms_max) << ',' << number(r.cpu_ms) << ",\""
        << r.passes << "\"," << r.mesh_bytes << ',' << number(r.error.rmse) << ',' << number(r.error.max_abs) << ','
        << number(r.error.psnr_db) << ',' << number(r.ssim) << ',' << (std::isnan(r.flip) ? "" : number(r.flip)) << ','
        << number(r.peak) << ',' << r.error.non_finite << ','
        << number(r.reference_ms) << ',' << (r.pareto ? 1 : 0) << ',' << r.shaded << ',' << r.mode_bytes << ','
        << optional_number(r.sm_mhz_min) << ',' << optional_number(r.sm_mhz_median) << ',' << optional_number(r.sm_mhz_max) << ",\""
        << r.space << "\"\n";
  out.close();
  if (!out) throw InputError(path.string(), "cannot write the CSV");
}

std::vector<std::string> csv_fields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (char ch : line) {
    if (ch == '"') quoted = !quoted;
    else if (ch == ',' && !quoted) fields.emplace_back();
    else fields.back() += ch;
  }
  return fields;
}

namespace {

double csv_number(const std::string& s) {
  if (s.empty() || s == "null") return std::numeric_limits<double>::quiet_NaN();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  size_t used = 0;
  const double v = std::stod(s, &used);
  if (used != s.size()) throw std::invalid_argument(s);
  return v;
}

}  // namespace

std::vector<BenchRow> read_csv(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open the bench CSV");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path.string(), "is empty: no header line");
  const std::vector<std::string> header = csv_fields(line);
  const auto column = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end()) throw InputError(path.string(), std::string("has no column '") + name + "' (not a prismoid bench CSV?)");
    return size_t(it - header.begin());
  };
  const size_t dataset = column("dataset"), cells = column("cells"), sweep = column("sweep"), quantity = column("quantity"),
               mode = column("mode"), settings = column("settings"), ordering = column("ordering"), timer = column("timer"),
               width = column("width"), height = column("height"), frames = column("frames"), ms_median = column("ms_median"),
               ms_min = column("ms_min"), ms_max = column("ms_max"), cpu_ms = column("cpu_ms"), passes = column("passes"),
               mesh_bytes = column("mesh_bytes"), rmse = column("rmse"), max_abs = column("max_abs"), psnr = column("psnr_db"),
               ssim = column("ssim"), flip = column("flip_mean"), peak = column("peak"), non_finite = column("non_finite"),
               reference_ms = column("reference_ms"), pareto = column("pareto");
  // Added later: CSVs written before have none of them (read as 0, the clock as not sampled).
  const auto optional_column = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? header.size() : size_t(it - header.begin());
  };
  const size_t shaded = optional_column("shaded"), mode_bytes = optional_column("mode_bytes"), sm_min = optional_column("sm_mhz_min"),
               sm_median = optional_column("sm_mhz_median"), sm_max = optional_column("sm_mhz_max"), space = optional_column("space");
  std::vector<BenchRow> rows;
  for (size_t number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const std::vector<std::string> f = csv_fields(line);
    if (f.size() != header.size())
      throw InputError(path.string(), "line " + std::to_string(number) + " has " + std::to_string(f.size()) + " fields, the header " +
                                          std::to_string(header.size()));
    try {
      BenchRow r;
      r.dataset = f[dataset];
      r.cells = std::stoull(f[cells]);
      r.sweep = f[sweep];
      r.quantity = f[quantity];
      r.mode = f[mode];
      r.settings = f[settings];
      r.ordering = f[ordering];
      r.timer = f[timer];
      r.width = uint32_t(std::stoul(f[width]));
      r.height = uint32_t(std::stoul(f[height]));
      r.frames = uint32_t(std::stoul(f[frames]));
      r.ms_median = csv_number(f[ms_median]);
      r.ms_min = csv_number(f[ms_min]);
      r.ms_max = csv_number(f[ms_max]);
      r.cpu_ms = csv_number(f[cpu_ms]);
      r.passes = f[passes];
      r.mesh_bytes = std::stoull(f[mesh_bytes]);
      r.error.rmse = csv_number(f[rmse]);
      r.error.max_abs = csv_number(f[max_abs]);
      r.error.psnr_db = csv_number(f[psnr]);
      r.ssim = csv_number(f[ssim]);
      r.flip = csv_number(f[flip]);
      r.peak = csv_number(f[peak]);
      r.error.non_finite = std::stoull(f[non_finite]);
      r.reference_ms = csv_number(f[reference_ms]);
      r.pareto = f[pareto] == "1";
      if (shaded < f.size()) r.shaded = std::stoull(f[shaded]);
      if (mode_bytes < f.size()) r.mode_bytes = std::stoull(f[mode_bytes]);
      if (sm_min < f.size()) r.sm_mhz_min = csv_number(f[sm_min]);
      if (space < f.size()) r.space = f[space];
      if (sm_median < f.size()) r.sm_mhz_median = csv_number(f[sm_median]);
      if (sm_max < f.size()) r.sm_mhz_max = csv_number(f[sm_max]);
      rows.push_back(std::move(r));
    } catch (const std::logic_error&) {  // stoull/stod: invalid_argument, out_of_range
      throw InputError(path.string(), "line " + std::to_string(number) + " has a field that is not a number where one belongs");
    }
  }
  return rows;
}

void write_report(const std::filesystem::path& path, const std::vector<BenchRow>& rows, const ReportContext& c) {
  std::ofstream out(path);
  out << "# prismoid bench\n\n- device: " << c.device << "\n- driver: " << c.driver << "\n";
  if (!c.host.empty()) out << "- host: " << c.host << "\n";
  out << "- command: `" << c.command << "`\n"
      << "- error: against the CPU double-precision reference; optical depth and transmittance compare the quantity\n"
      << "  (PSNR peak: the reference's largest optical depth, or 1), color the display RGB (peak 1; surfaces: their\n"
      << "  linear radiance clamped to [0, 1], as the window and PNGs show it); SSIM: mean\n"
      << "  structural similarity (Wang et al. 2004, 11x11 Gaussian window) on the same channels and peak; FLIP\n"
      << "  (colour only): mean LDR-FLIP (Andersson et al. 2020) at 67 pixels per degree, 0 = identical, 1 = most different\n"
      << "- time: `gpu` rows are GPU timestamps around the frame's passes (median over the timed frames, best-worst\n"
      << "  beside it); `wall` rows are CPU wall clock: VTK's mappers' of a whole frame ending in glFinish, the time\n"
      << "  sweep's step switches' from a step's mesh in memory to its frame read back (its upload included);\n"
      << "  SM MHz: the GPU's SM clock during the timed frames (median, min-max), where nvidia-smi is on PATH (frames shorter\n"
         "  than its 100 ms period: the half second of warm-up before them)\n"
      << "- `*`: Pareto-optimal among the rows of its dataset, quantity and image size (no other row is both at\n"
      << "  least as fast and at least as accurate)\n";
  for (const auto& n : c.notes) out << "- " << n << "\n";
  if (!c.plots.empty()) {
    out << "\n## Plots\n\n";
    for (const auto& [title, file] : c.plots) out << "- [" << title << "](" << file << ")\n";
  }
  write_findings(out, rows);
  std::vector<std::string> datasets;
  for (const auto& r : rows)
    if (std::find(datasets.begin(), datasets.end(), r.dataset) == datasets.end()) datasets.push_back(r.dataset);
  for (const auto& d : datasets) {
    std::vector<const BenchRow*> sorted;
    for (const auto& r : rows)
      if (r.dataset == d) sorted.push_back(&r);
    std::stable_sort(sorted.begin(), sorted.end(), [](auto* a, auto* b) {
      if (a->quantity != b->quantity) return a->quantity < b->quantity;
      if (a->width * a->height != b->width * b->height) return a->width * a->height < b->width * b->height;
      return a->ms_median < b->ms_median;
    });
    // The mesh's GPU buffers, as the GPU rows measured them: VTK's mappers' rows (mesh 0: not
    // ours to measure) may sort first.
    uint64_t mesh_bytes = 0;
    for (const auto* r : sorted) mesh_bytes = std::max(mesh_bytes, r->mesh_bytes);
    out << "\n## " << d << " (" << sorted.front()->cells << " cells, mesh " << mib(mesh_bytes) << " MiB on the GPU)\n\n"
        << "| | quantity | size | mode | settings | sweep | ms (median) | best-worst | timer | CPU ms | RMSE | max abs | PSNR dB | SSIM | FLIP | reference ms | shaded | mode MiB | SM MHz |\n"
        << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto* r : sorted)
      out << "| " << (r->pareto ? "*" : "") << " | " << r->quantity << " | " << r->width << "x" << r->height << " | " << r->mode
          << " | " << r->settings << " | " << r->sweep << " | " << fixed(r->ms_median, 4) << " | " << fixed(r->ms_min, 4) << "-"
          << fixed(r->ms_max, 4) << " | " << r->timer << " | " << fixed(r->cpu_ms, 3) << " | " << fixed(r->error.rmse, 3) << " | "
          << fixed(r->error.max_abs, 3) << " | " << fixed(r->error.psnr_db, 4) << " | " << fixed(r->ssim, 6) << " | "
          << (std::isnan(r->flip) ? std::string("-") : fixed(r->flip, 4)) << " | " << fixed(r->reference_ms, 4)
          << (r->error.non_finite ? " (non-finite: " + std::to_string(r->error.non_finite) + ")" : "") << " | "
          << (r->shaded ? std::to_string(r->shaded) : std::string("-")) << " | " << (r->mode_bytes ? mib(r->mode_bytes) : std::string("-"))
          << " | "
          << (std::isnan(r->sm_mhz_median) ? std::string("-")
                                           : fixed(r->sm_mhz_median, 5) + " (" + fixed(r->sm_mhz_min, 5) + "-" + fixed(r->sm_mhz_max, 5) + ")")
          << " |\n";
  }
  out.close();
  if (!out) throw InputError(path.string(), "cannot write the report");
}

}  // namespace prismoid::bench
