#pragma once
// What the bench's `time` sweep must write for a dataset of N time steps (a series or an Exodus
// file), read back through the bench's own CSV reader: each step's transmittance row and colour
// row, in step order, each naming that step; then the four step switches (each step uploaded whole,
// then its fields alone; the mesh backend, then the compute backend), timed on the wall clock.
// Every row's RMSE is against its own step's reference: against another step's, transmittance
// would be off by tenths.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "app/bench/bench_table.hpp"

namespace prismoid::test {

inline void expect_time_sweep_rows(const std::filesystem::path& csv, size_t steps, double largest_rmse = 1e-4) {
  const std::vector<bench::BenchRow> rows = bench::read_csv(csv);
  ASSERT_EQ(rows.size(), 2 * steps + 4);
  for (size_t i = 0; i < rows.size(); ++i) {
    const bench::BenchRow& row = rows[i];
    SCOPED_TRACE("row " + std::to_string(i) + ": " + row.dataset + " " + row.quantity + " " + row.settings);
    EXPECT_EQ(row.sweep, "time");
    if (i < 2 * steps) {
      const std::string step = std::to_string(i / 2);
      EXPECT_NE(row.dataset.find("step " + step + " (t = "), std::string::npos);
      EXPECT_EQ(row.quantity, i % 2 ? "color" : "transmittance");
      EXPECT_NE(row.settings.find("time-step=" + step), std::string::npos);
    } else {
      const size_t k = i - 2 * steps;
      EXPECT_NE(row.settings.find(std::string("step-switch=") + (k % 2 ? "fields" : "whole")), std::string::npos);
      EXPECT_EQ(row.settings.find("volume-backend=compute") != std::string::npos, k >= 2);
      EXPECT_EQ(row.timer, "wall");
    }
    EXPECT_LT(row.error.rmse, largest_rmse);
  }
}

}  // namespace prismoid::test
