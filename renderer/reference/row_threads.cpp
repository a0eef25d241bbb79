#include "renderer/reference/row_threads.hpp"

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace prismoid::reference {

void for_row_phases(uint32_t rows, const std::function<void(RowPhase rows)>& work) {
  const uint32_t threads = std::max(1u, std::min(rows, std::thread::hardware_concurrency()));
  std::exception_ptr failure;
  std::mutex failure_lock;
  auto run = [&](uint32_t phase) {
    try {
      work(RowPhase{phase, threads});
    } catch (...) {
      const std::lock_guard<std::mutex> hold(failure_lock);
      if (!failure) failure = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(run, t);
  run(0);
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

void for_each_pixel_in_parallel(uint32_t width, uint32_t height, const std::function<void(size_t pixel)>& work) {
  for_row_phases(height, [&](RowPhase rows) {
    for (uint32_t y = rows.phase; y < height; y += rows.step)
      for (uint32_t x = 0; x < width; ++x) work(size_t(y) * width + x);
  });
}

}  // namespace prismoid::reference
