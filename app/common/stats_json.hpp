#pragma once
// The stats file every render verb writes (--stats), built as nlohmann::ordered_json (keys in the
// order they are set) and written in one layout: a key a line, arrays of objects an object a
// line, other arrays and objects on their key's line, numbers to 9 significant digits (null for
// NaN and infinities). Tests and scripts read the files by key; the layout keeps them readable.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/timing/frame_timing.hpp"
#include "renderer/vk/timer.hpp"

namespace prismoid::mixed {
struct MixedPlan;
}

namespace prismoid::app {

using StatsJson = nlohmann::ordered_json;

// The text of a stats object (a JSON object, ending in a newline).
std::string format_stats(const StatsJson& stats);
// Writes format_stats(stats) to `path` (an OutputFiles temporary); InputError naming the file
// when it cannot be written.
void write_stats(const std::string& path, const StatsJson& stats);

// "passes": each pass's name and GPU time ("gpu_ms"), and where frames were timed its best and
// worst over them ("min_ms", "max_ms"; gpu_ms is then the median).
StatsJson passes_json(const std::vector<vk::PassTiming>& passes);
StatsJson passes_json(const timing::FrameTiming& timing);
// "cpu_passes": each CPU stage's name and time ("cpu_ms"; PassTiming::gpu_ms holds it).
StatsJson cpu_passes_json(const std::vector<vk::PassTiming>& passes);
// Sets "sm_clock_mhz" ({"min", "median", "max", "samples"}) where the clock was sampled.
void add_sm_clock(StatsJson& stats, const timing::FrameTiming& timing);
// Sets "plan" (each planned pass: name, kind gpu|cpu|within, reason) and "skipped" (pass, reason).
void add_plan(StatsJson& stats, const frame::FramePlan& plan);
// The same for a volume inside its surfaces: the surfaces' passes, the volume's, the composite,
// each with "part" (surfaces, volume, composite), and the skips of both.
void add_plan(StatsJson& stats, const mixed::MixedPlan& plan);

}  // namespace prismoid::app
