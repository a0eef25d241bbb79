// The bench's plain parts: which cases a preset measures, and which rows are Pareto-optimal.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <gtest/gtest.h>
#include <unistd.h>

#include "app/bench/bench_cases.hpp"
#include "app/bench/bench_table.hpp"
#include "scene/input_error.hpp"

namespace prismoid::bench {
namespace {

bool has(const std::vector<BenchCase>& cases, const std::string& sweep) {
  return std::any_of(cases.begin(), cases.end(), [&](const BenchCase& c) { return c.sweep == sweep; });
}

TEST(BenchCases, TheCellSweepStopsAtTheLargestMeshThatFits) {
  BenchPreset p{.quick = false, .size = {400, 300}, .max_cells = field_cells(48)};
  std::set<std::string> meshes;
  for (const auto& c : bench_cases({"a.vtu"}, p))
    if (c.sweep == "cells") meshes.insert(c.dataset);
  EXPECT_EQ(meshes, (std::set<std::string>{"field:marschner-lobb:6", "field:marschner-lobb:12", "field:marschner-lobb:24",
                                           "field:marschner-lobb:48"}));
  p.max_cells = field_cells(6) - 1;  // not even the smallest: no cell sweep, everything else stays
  const auto none = bench_cases({"a.vtu"}, p);
  EXPECT_FALSE(has(none, "cells"));
  EXPECT_TRUE(has(none, "modes") && has(none, "march-step"));
}

TEST(BenchCases, ImageSizesAreHalfAndTwiceOnTheFirstDatasetOnly) {
  const BenchPreset p{.quick = false, .size = {400, 300}, .max_cells = 0};
  std::set<std::pair<uint32_t, uint32_t>> sizes;
  for (const auto& c : bench_cases({"a.vtu", "b.vtu"}, p)) {
    if (c.sweep == "image-size") {
      EXPECT_EQ(c.dataset, "a.vtu");
      sizes.insert({c.size.width, c.size.height});
    } else {
      EXPECT_EQ(c.size, (ImageSize{400, 300})) << c.sweep;
    }
  }
  EXPECT_EQ(sizes, (std::set<std::pair<uint32_t, uint32_t>>{{200, 150}, {800, 600}}));
}

TEST(BenchCases, TheQuickPresetIsASubsetOfTheFullOne) {
  const BenchPreset full{.quick = false, .size = {96, 72}, .max_cells = 1'000'000};
  BenchPreset quick = full;
  quick.quick = true;
  const auto all = bench_cases({"", "ball:2"}, full);
  const auto some = bench_cases({"", "ball:2"}, quick);
  EXPECT_LT(some.size(), all.size());
  for (const auto& c : some) {
    if (c.sweep == "march-step" || c.sweep == "cells") continue;  // the quick preset uses smaller fields
    EXPECT_TRUE(std::any_of(all.begin(), all.end(), [&](const BenchCase& o) {
      return o.dataset == c.dataset && o.sweep == c.sweep && o.mode == c.mode && o.quantity == c.quantity && o.options == c.options;
    })) << c.dataset << " " << c.sweep << " " << settings_label(c);
  }
  for (const char* s : {"modes", "tetlet-size", "preintegration", "march-step", "cells"}) EXPECT_TRUE(has(some, s)) << s;
}

BenchRow row(const std::string& dataset, const std::string& quantity, double ms, double rmse, uint32_t width = 100) {
  BenchRow r;
  r.dataset = dataset;
  r.quantity = quantity;
  r.ms_median = ms;
  r.error.rmse = rmse;
  r.width = width;
  r.height = 100;
  return r;
}

TEST(BenchTable, ParetoRowsAreThoseNoComparableRowBeats) {
  std::vector<BenchRow> rows = {
      row("d", "color", 1.0, 0.5),   // fastest: optimal
      row("d", "color", 2.0, 0.1),   // slower, more accurate: optimal
      row("d", "color", 3.0, 0.1),   // as accurate as the row above, slower: dominated
      row("d", "color", 2.0, 0.1),   // a tie with row 1: neither beats the other
      row("d", "optical-depth", 9.0, 9.0),  // the only row of its quantity: optimal
      row("e", "color", 9.0, 9.0),          // another dataset: not weighed against d
      row("d", "color", 0.5, 0.05, 50),     // another image size: not weighed against the 100-wide rows
      row("d", "color", 0.1, std::numeric_limits<double>::quiet_NaN()),  // a NaN error: never optimal
  };
  mark_pareto(rows);
  std::vector<bool> pareto;
  for (const auto& r : rows) pareto.push_back(r.pareto);
  EXPECT_EQ(pareto, (std::vector<bool>{true, true, false, true, true, true, true, false}));
}

TEST(BenchTable, TheCsvHasOneLinePerRowAndTheReportOneTablePerDataset) {
  const auto dir = std::filesystem::temp_directory_path() / ("prismoid-test-bench-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<BenchRow> rows = {row("d", "color", 1.0, 0.5), row("e", "color", 2.0, 0.25)};
  rows[1].error.psnr_db = std::numeric_limits<double>::infinity();
  mark_pareto(rows);
  write_csv(dir / "bench.csv", rows);
  write_report(dir / "report.md", rows, {.device = "dev", .driver = "drv", .command = "prismoid bench", .plots = {{"t", "p.png"}}});
  std::ifstream csv(dir / "bench.csv");
  std::vector<std::string> lines;
  for (std::string l; std::getline(csv, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_NE(lines[2].find(",inf,"), std::string::npos) << lines[2];  // an infinite PSNR is written as inf, not null
  std::ifstream md(dir / "report.md");
  std::stringstream text;
  text << md.rdbuf();
  EXPECT_NE(text.str().find("\n## d ("), std::string::npos);
  EXPECT_NE(text.str().find("\n## e ("), std::string::npos);
  EXPECT_NE(text.str().find("[t](p.png)"), std::string::npos);
  EXPECT_THROW(write_csv(dir / "missing" / "bench.csv", rows), std::exception);
  std::filesystem::remove_all(dir);
}

// A dataset's heading gives the mesh's GPU memory as the GPU rows measured it, also where a
// row of VTK's mappers (mesh 0: their memory is not ours to measure) sorts first, as the fast
// colour rows of a dataset with a scalar array do.
TEST(BenchTable, TheReportsMeshMemoryIsTheGpuRowsEvenWhereAPeerRowSortsFirst) {
  const auto dir = std::filesystem::temp_directory_path() / ("prismoid-test-bench-mesh-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<BenchRow> rows = {row("d", "transmittance", 2.0, 0.1), row("d", "color", 1.0, 0.2)};
  rows[0].mesh_bytes = 4718592;  // 4.5 MiB
  rows[1].timer = "wall";       // VTK's mapper: first in the table (colour, fastest)
  write_report(dir / "report.md", rows, {.device = "dev", .driver = "drv", .command = "prismoid bench"});
  std::ifstream md(dir / "report.md");
  std::stringstream text;
  text << md.rdbuf();
  EXPECT_NE(text.str().find("## d (0 cells, mesh 4.5 MiB on the GPU)"), std::string::npos) << text.str();
  std::filesystem::remove_all(dir);
}

TEST(BenchTable, TheCsvReadsBackAsWritten) {
  const auto dir = std::filesystem::temp_directory_path() / ("prismoid-test-bench-csv-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<BenchRow> rows = {row("d, with a comma", "color", 1.25, 0.5), row("e", "optical-depth", 2.0, 0.0)};
  rows[0].settings = "tetlet-size=1 preintegration-size=16";
  rows[0].passes = "interval=1.0;resolve=0.25";
  rows[0].flip = 0.125;
  rows[0].timer = "wall";
  rows[1].error.psnr_db = std::numeric_limits<double>::infinity();
  rows[1].cells = 12'582'912;
  rows[1].mesh_bytes = 1ull << 33;
  rows[1].shaded = 123'456'789'012ull;
  rows[1].mode_bytes = 1ull << 26;
  mark_pareto(rows);
  write_csv(dir / "bench.csv", rows);
  const std::vector<BenchRow> back = read_csv(dir / "bench.csv");
  ASSERT_EQ(back.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back[i].dataset, rows[i].dataset);
    EXPECT_EQ(back[i].settings, rows[i].settings);
    EXPECT_EQ(back[i].passes, rows[i].passes);
    EXPECT_EQ(back[i].timer, rows[i].timer);
    EXPECT_EQ(back[i].cells, rows[i].cells);
    EXPECT_EQ(back[i].mesh_bytes, rows[i].mesh_bytes);
    EXPECT_EQ(back[i].ms_median, rows[i].ms_median);
    EXPECT_EQ(back[i].error.rmse, rows[i].error.rmse);
    EXPECT_EQ(back[i].error.psnr_db, rows[i].error.psnr_db);
    EXPECT_EQ(back[i].pareto, rows[i].pareto);
    EXPECT_EQ(back[i].shaded, rows[i].shaded);
    EXPECT_EQ(back[i].mode_bytes, rows[i].mode_bytes);
  }
  EXPECT_EQ(back[0].flip, 0.125);
  EXPECT_TRUE(std::isnan(back[1].flip));  // no colour: no FLIP, written empty
  // A file that is not the bench's CSV, and a row that lost a field, are errors naming the file.
  std::ofstream(dir / "other.csv") << "a,b\n1,2\n";
  std::ofstream(dir / "short.csv") << std::ifstream(dir / "bench.csv").rdbuf() << "\"x\",1,2\n";
  for (const char* bad : {"other.csv", "short.csv", "missing.csv"}) {
    try {
      read_csv(dir / bad);
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace prismoid::bench
