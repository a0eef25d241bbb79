#pragma once
// The bench's plots: scatter and line charts drawn with VTK's charts (vtkChartXY) and written as
// PNG. Plain structs in, a file out; VTK stays inside bench_plot.cpp.
//
// Debian's VTK renders through GLX only, so drawing needs an X display (Xvfb will do): with
// DISPLAY unset or unreachable, write_plot_png throws std::runtime_error saying so.
#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace prismoid::bench {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};

struct PlotPoint {
  double x = 0, y = 0;
  std::string label;  // drawn beside the point when not empty
};

struct PlotSeries {
  std::string name;  // the legend's entry
  std::vector<PlotPoint> points;
  bool line = false;          // join the points in their order (markers drawn too)
  std::optional<Rgb> color;   // default: series_color(index of the series)
};

struct PlotSpec {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<PlotSeries> series;
  // Pareto-optimal points (for minimising both x and y); drawn as a dashed staircase in
  // pareto_color() under the series' markers, from the top of the y axis down to the point of
  // least x, through the front, and on to the right end of the x axis. Empty: no front.
  std::vector<PlotPoint> pareto_front;
  uint32_t width = 960, height = 640;
};

// One axis of a written plot: a data value maps linearly (in log10 of the value on a log axis)
// from [data_min, data_max] to [pixel_min, pixel_max].
struct PlotAxisMap {
  bool log = false;
  double data_min = 0, data_max = 1;
  double pixel_min = 0, pixel_max = 1;
  double to_pixel(double value) const;
};

// Where data landed in the written image, read back from the chart's axes after rendering.
// Pixel coordinates have a top-left origin; pixel (i, j) covers [i, i+1) x [j, j+1).
struct PlotLayout {
  uint32_t width = 0, height = 0;
  PlotAxisMap x, y;
  size_t plotted = 0;       // series points drawn
  size_t non_finite = 0;    // points dropped for a non-finite coordinate (series and front)
  size_t non_positive = 0;  // points dropped for a value <= 0 on a log axis (series and front)
  std::string note;         // what was left out, as printed under the title; empty when nothing
  // The point's pixel; nullopt where the point cannot be drawn (non-finite, <= 0 on a log axis).
  std::optional<std::array<double, 2>> pixel_of(double x, double y) const;
};

// Draws the plot and writes it to png (removed again when the write fails; putting it in place
// whole is the caller's, app/common/output_files.hpp). A plot with no drawable point is still written,
// with "no data" under the title.
// Throws InputError naming png when it cannot be written (missing folder, a folder in its place,
// no permission), std::runtime_error without an X display, std::invalid_argument for a zero size.
PlotLayout write_plot_png(const PlotSpec& spec, const std::filesystem::path& png);

Rgb series_color(size_t index);  // a palette of 8 distinct colours, repeating
Rgb pareto_color();              // the front's staircase: black

// --- The bench's two kinds of plot, from its rows -------------------------------------------

// One measurement of the bench: one dataset rendered in one configuration.
struct BenchPoint {
  std::string dataset, quantity, mode;
  std::string label;  // the configuration's settings beyond the mode ("" for none)
  size_t cells = 0;
  double gpu_ms = 0;  // GPU time per frame
  double error = 0;   // against the CPU reference (the bench's RMSE)
  uint32_t width = 0, height = 0;  // the image's size (0: not given); errors of different sizes
                                   // are not compared
};

// A surface row on the shading-rate plot: its scene, the configuration it belongs to (mode and
// settings but the rate), its rate's label, the samples it shaded per frame and its mean FLIP.
struct RatePoint {
  std::string dataset, series, label;
  double samples = 0;
  double flip = 0;
};

// Per scene (and image size, in the dataset name the caller gives), FLIP against the samples
// shaded per frame, log-log, a line per configuration through its rates:
// flip_vs_samples_<dataset>.png. Scenes with fewer than two points get none.
std::vector<std::pair<std::string, PlotSpec>> shading_rate_plots(const std::vector<RatePoint>& points);

// The plots of a bench run, each with its file name (no folder):
// - per dataset, quantity and image size, error against GPU time, log-log, a series per mode with
//   the points labelled by their settings, and the Pareto front (within that dataset, quantity
//   and size) marked: error_vs_time_<dataset>_<quantity>[_<W>x<H>].png;
// - one plot of GPU time against the dataset's cell count, log-log, a line per configuration
//   (quantity, mode, settings, size) through the datasets in cell order: time_vs_cells.png.
// Datasets, quantities and sizes keep the order they first appear in; names are made file-safe
// and unique.
std::vector<std::pair<std::string, PlotSpec>> bench_plots(const std::vector<BenchPoint>& points);

}  // namespace prismoid::bench
