#pragma once
// The bench's measurements as rows, and the files made of them: bench.csv (every row) and
// report.md (the machine, the command, a table per dataset, the plots). Plain data, no Vulkan.
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "renderer/metrics/image_error.hpp"
#include "renderer/timing/frame_timing.hpp"

namespace prismoid::bench {

struct BenchRow {
  std::string dataset;  // the mesh's name
  uint64_t cells = 0;
  std::string sweep, quantity, mode, settings;
  std::string ordering;  // the ordering the renderer reports having used
  std::string timer = "gpu";  // "gpu": timestamp queries around the passes; "wall": CPU wall clock
                              // of a whole frame ending in a GPU finish (the VTK peers)
  uint32_t width = 0, height = 0, frames = 0;
  double ms_median = 0, ms_min = 0, ms_max = 0;  // per frame, over the timed frames: median, best, worst
  // The SM clock during the timed frames (nvidia-smi); NaN where it was not sampled.
  double sm_mhz_min = std::numeric_limits<double>::quiet_NaN(), sm_mhz_median = std::numeric_limits<double>::quiet_NaN(),
         sm_mhz_max = std::numeric_limits<double>::quiet_NaN();
  double cpu_ms = 0;        // CPU stages the frame needed (median), e.g. the exact order
  std::string passes;       // name=median ms, in order, ';'-separated
  uint64_t mesh_bytes = 0;  // the mesh's GPU buffers
  uint64_t shaded = 0;      // surfaces: shading-code invocations per measured frame, the mean (pixels or texels); 0: not counted
  uint64_t mode_bytes = 0;  // surfaces: the mode's own GPU memory beyond the scene (Htex: pool and tables)
  // surfaces: what the mode measured of its own shading space, name=value ';'-separated: Sander's
  // stretch between screen and atlas (stretch_l2, stretch_linf: FastAtlas, msa) and FastAtlas's
  // atlas fill; empty: none.
  std::string space;
  reference::ImageError error;
  double ssim = 0;          // mean structural similarity to the reference
  double flip = std::numeric_limits<double>::quiet_NaN();  // colour only: mean LDR-FLIP (NaN: none)
  double peak = 1.0;        // the PSNR's peak
  double reference_ms = 0;  // the CPU reference's time for this image
  bool pareto = false;
};

// The row's times from its timed frames: the frames' totals (median, best, worst), each pass's
// median, and the SM clock where it was sampled.
void set_times(BenchRow& row, const timing::FrameTiming& timing);

// Marks the rows no other row of the same dataset, quantity and image size (and, for the mixed
// sweep's rows, of that sweep) beats: at least as
// fast and at least as accurate (RMSE), and better in one. Errors of different quantities or
// sizes are not comparable, so they are never weighed against each other. Non-finite errors are
// never optimal.
void mark_pareto(std::vector<BenchRow>& rows);

void write_csv(const std::filesystem::path& path, const std::vector<BenchRow>& rows);
// One CSV line's fields; quoted fields may hold commas.
std::vector<std::string> csv_fields(const std::string& line);

// The rows write_csv wrote (error fields beyond RMSE, max, PSNR and the non-finite count are not
// kept); InputError naming the file and line for anything else.
std::vector<BenchRow> read_csv(const std::filesystem::path& path);

struct ReportContext {
  std::string device, driver, command, host;
  std::vector<std::string> notes;                           // lines said once, at the top
  std::vector<std::pair<std::string, std::string>> plots;   // title, file name beside report.md
};
void write_report(const std::filesystem::path& path, const std::vector<BenchRow>& rows, const ReportContext& context);

}  // namespace prismoid::bench
