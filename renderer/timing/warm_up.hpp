#pragma once
// Frames before timed ones, shared by `render --frames N`, the bench and the surface bench.
#include <cstdint>
#include <functional>

namespace prismoid::timing {

// Draws `frame`, which returns its GPU time in ms, until `seconds` of wall clock have passed and
// the frames have stopped getting faster (the median of the last 4 within 2% of the 4 before), for
// 4 x `seconds` at most (just `seconds` where a frame's time is NaN: no timestamps), and at least
// once (pipelines, caches, first-use work); returns how many frames that took. A row's timed
// frames follow at once, and the frames should keep the GPU busy (no read-back between them).
// Why: after an idle spell (the bench computes each CPU reference between rows) a GPU can stay at
// its idle clock through a row's frames, and under frames with read-backs between them it rises
// only slowly; rows timed then are several times too slow (docs/results.md, "The GPU's clock",
// has the measurements).
uint32_t warm_up(const std::function<double()>& frame, double seconds);
// The warm-up of `prismoid render --frames N` (N > 1) and the bench's default.
inline constexpr double kTimedWarmUpSeconds = 2.0;

}  // namespace prismoid::timing
