#pragma once
// What a run of timed frames measured, summarized once for every verb that times frames
// (`render --frames N` of volumes and surfaces, the bench's volume and surface rows): per pass the
// best, median and worst GPU time over the frames, the same for the frames' totals, and, where
// nvidia-smi is on PATH, the SM clock the GPU ran at meanwhile (a GPU that stays at a low clock
// makes every time several times too slow: the clock says which times to trust).
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "renderer/vk/timer.hpp"

namespace prismoid::timing {

// The median of the finite values (the mean of the middle two for an even count); NaN for none.
double median_of(std::vector<double> values);

// Best (smallest), median and worst (largest) of the finite values; all NaN for none (a device
// without timestamps).
struct Spread {
  double best = 0.0, median = 0.0, worst = 0.0;
};
Spread spread_of(const std::vector<double>& values);

struct PassSpread {
  std::string name;
  Spread ms;
};

// The SM clock in MHz over the samples taken.
struct ClockSpread {
  double min_mhz = 0.0, median_mhz = 0.0, max_mhz = 0.0;
  size_t samples = 0;
};

struct FrameTiming {
  uint32_t frames = 0;
  std::vector<PassSpread> passes;  // the first frame's passes, in order, each over every frame
  Spread total_ms;                 // each frame's passes summed
  std::optional<ClockSpread> sm_clock;  // absent: nvidia-smi is not on PATH, or gave no sample
  // The passes with their median times, as the verbs print and store a frame's passes.
  std::vector<vk::PassTiming> medians() const;
};

// The passes of `frames` (each frame's PassTimings) summarized: the k-th pass named N of every
// frame is one pass, so passes that repeat a name in a frame stay apart and a frame that lacks a
// pass does not shift the others. No sm_clock (time_frames samples it).
FrameTiming summarize_frames(const std::vector<std::vector<vk::PassTiming>>& frames);

// nvidia-smi's SM clock, sampled every 100 ms from a child process
// (`nvidia-smi --query-gpu=clocks.sm --format=csv,noheader,nounits -lms 100`) for as long as the
// object lives or until stop(). Nothing is sampled where nvidia-smi is not on PATH or prints no
// numbers (no NVIDIA driver). With several NVIDIA GPUs every GPU's lines count.
class SmClockSampler {
 public:
  SmClockSampler();
  ~SmClockSampler();
  SmClockSampler(const SmClockSampler&) = delete;
  SmClockSampler& operator=(const SmClockSampler&) = delete;
  using Clock = std::chrono::steady_clock;
  // Ends the child and returns the samples taken since construction. nvidia-smi needs a moment
  // to start: where no sample came while it ran, the first one it prints after (within a second)
  // stands for the run. nullopt where there is none.
  std::optional<ClockSpread> stop();
  // The samples that arrived in [from, to]. Where none did (timed frames are often shorter than
  // nvidia-smi's 100 ms period), those of the half second before `from`, taken while the frames
  // before (a warm-up's) kept the GPU as busy as the timed ones; failing that, the first
  // one after `to`, waiting up to a second for it (the GPU has idled by then: the clock reads low).
  // The child keeps running. nullopt where there is none.
  std::optional<ClockSpread> during(Clock::time_point from, Clock::time_point to);
  // Whether the child still runs (nvidia-smi was found and has not ended).
  bool running();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Starts the process's own SM clock sampler where none runs, so that its samples already come
// when timed frames start: warm_up() calls it, time_frames() reads it. Cheap where nvidia-smi is
// not on PATH (one failed spawn).
SmClockSampler* process_sm_clock();
// Ends that sampler (the next process_sm_clock() starts another).
void stop_process_sm_clock();

// Times `frames` calls of `frame` (which draws one frame and returns its passes' GPU times), with
// the SM clock sampled meanwhile; frames > 0.
FrameTiming time_frames(uint32_t frames, const std::function<std::vector<vk::PassTiming>()>& frame);

}  // namespace prismoid::timing
