#include "app/common/stats_json.hpp"

#include <algorithm>
#include <fstream>

#include "app/common/cli_args.hpp"
#include "renderer/mixed/mixed_frame.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

// A value on one line: objects as {"k": v, ...}, arrays as [a, b], numbers as json_number.
std::string inline_text(const StatsJson& v) {
  if (v.is_object()) {
    std::string s = "{";
    bool first = true;
    for (const auto& [key, value] : v.items()) {
      s += (first ? "" : ", ") + StatsJson(key).dump() + ": " + inline_text(value);
      first = false;
    }
    return s + "}";
  }
  if (v.is_array()) {
    std::string s = "[";
    for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + inline_text(v[i]);
    return s + "]";
  }
  if (v.is_number_float()) return json_number(v.get<double>());
  // Strings as they are (UTF-8 kept), with anything that is not valid UTF-8 replaced rather than
  // failing the whole file.
  return v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

bool array_of_objects(const StatsJson& v) {
  return v.is_array() && !v.empty() && std::all_of(v.begin(), v.end(), [](const StatsJson& e) { return e.is_object(); });
}

}  // namespace

std::string format_stats(const StatsJson& stats) {
  std::string s = "{";
  bool first = true;
  for (const auto& [key, value] : stats.items()) {
    s += (first ? "\n  " : ",\n  ") + StatsJson(key).dump() + ": ";
    first = false;
    if (!array_of_objects(value)) {
      s += inline_text(value);
      continue;
    }
    s += "[";
    for (size_t i = 0; i < value.size(); ++i) s += (i ? ",\n    " : "\n    ") + inline_text(value[i]);
    s += "\n  ]";
  }
  return s + "\n}\n";
}

void write_stats(const std::string& path, const StatsJson& stats) {
  const std::string text = format_stats(stats);
  std::ofstream out(path);
  if (!out || !(out << text) || !out.flush()) throw InputError(path, "cannot write the stats file");
}

StatsJson passes_json(const std::vector<vk::PassTiming>& passes) {
  StatsJson list = StatsJson::array();
  for (const vk::PassTiming& p : passes) list.push_back({{"name", p.name}, {"gpu_ms", p.gpu_ms}});
  return list;
}

StatsJson cpu_passes_json(const std::vector<vk::PassTiming>& passes) {
  StatsJson list = StatsJson::array();
  for (const vk::PassTiming& p : passes) list.push_back({{"name", p.name}, {"cpu_ms", p.gpu_ms}});
  return list;
}

StatsJson passes_json(const timing::FrameTiming& timing) {
  StatsJson list = StatsJson::array();
  for (const timing::PassSpread& p : timing.passes)
    list.push_back({{"name", p.name}, {"gpu_ms", p.ms.median}, {"min_ms", p.ms.best}, {"max_ms", p.ms.worst}});
  return list;
}

void add_sm_clock(StatsJson& stats, const timing::FrameTiming& timing) {
  if (!timing.sm_clock) return;
  const timing::ClockSpread& c = *timing.sm_clock;
  stats["sm_clock_mhz"] = {{"min", c.min_mhz}, {"median", c.median_mhz}, {"max", c.max_mhz}, {"samples", c.samples}};
}

namespace {

void append_plan(StatsJson& passes, StatsJson& skipped, const frame::FramePlan& plan, const char* part) {
  for (const frame::PlannedPass& p : plan.passes) {
    const char* kind = p.kind == frame::PassKind::Gpu ? "gpu" : p.kind == frame::PassKind::Cpu ? "cpu" : "within";
    passes.push_back({{"name", p.name}, {"kind", kind}, {"reason", p.reason}});
    if (part) passes.back()["part"] = part;
  }
  for (const frame::SkippedPass& p : plan.skipped) {
    skipped.push_back({{"pass", p.name}, {"reason", p.reason}});
    if (part) skipped.back()["part"] = part;
  }
}

}  // namespace

void add_plan(StatsJson& stats, const frame::FramePlan& plan) {
  StatsJson passes = StatsJson::array(), skipped = StatsJson::array();
  append_plan(passes, skipped, plan, nullptr);
  stats["plan"] = std::move(passes);
  stats["skipped"] = std::move(skipped);
}

void add_plan(StatsJson& stats, const mixed::MixedPlan& plan) {
  StatsJson passes = StatsJson::array(), skipped = StatsJson::array();
  append_plan(passes, skipped, plan.surfaces, "surfaces");
  append_plan(passes, skipped, plan.volume, "volume");
  passes.push_back({{"name", mixed::kCompositePass}, {"kind", "cpu"}, {"reason", plan.composite}, {"part", "composite"}});
  stats["plan"] = std::move(passes);
  stats["skipped"] = std::move(skipped);
}

}  // namespace prismoid::app
