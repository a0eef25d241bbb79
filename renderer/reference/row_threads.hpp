#pragma once
// Spreads a CPU reference's rows over the machine's cores. Each row belongs to one thread, so
// every pixel's sum is formed by one thread in the order a single thread would form it: the
// images are bit for bit those of a serial run, whatever the thread count.
#include <cstddef>
#include <cstdint>
#include <functional>

namespace prismoid::reference {

// The rows y of an image with y % step == phase.
struct RowPhase {
  uint32_t phase = 0, step = 1;
  // The first such row at or after y (may lie beyond the image).
  uint32_t first_from(uint32_t y) const { return y + (phase + step - y % step) % step; }
};

// Calls work(rows) once per thread (std::thread::hardware_concurrency, at most `rows` of them),
// each with its own phase. Interleaved rows rather than bands: neighbouring rows cost about the
// same, so every thread gets a fair share of a volume that fills only the middle of the image.
// An exception thrown by any call is rethrown here after all threads have joined.
void for_row_phases(uint32_t rows, const std::function<void(RowPhase rows)>& work);

// Calls work(pixel) for every pixel of a width x height image, rows spread as above.
void for_each_pixel_in_parallel(uint32_t width, uint32_t height, const std::function<void(size_t pixel)>& work);

}  // namespace prismoid::reference
