#include "app/bench/bench_plot.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <tuple>

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContext2D.h>
#include <vtkContextItem.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include "app/bench/pareto.hpp"
#include "scene/input_error.hpp"

// Last: Xlib's macros (None, Status, Bool, ...) must not reach the headers above.
#include <X11/Xlib.h>

namespace prismoid::bench {

namespace fs = std::filesystem;

double PlotAxisMap::to_pixel(double value) const {
  const double v = log ? std::log10(value) : value;
  const double lo = log ? std::log10(data_min) : data_min;
  const double hi = log ? std::log10(data_max) : data_max;
  return pixel_min + (v - lo) / (hi - lo) * (pixel_max - pixel_min);
}

std::optional<std::array<double, 2>> PlotLayout::pixel_of(double px, double py) const {
  if (!std::isfinite(px) || !std::isfinite(py)) return std::nullopt;
  if ((x.log && px <= 0) || (y.log && py <= 0)) return std::nullopt;
  return std::array<double, 2>{x.to_pixel(px), y.to_pixel(py)};
}

Rgb series_color(size_t index) {
  // Okabe and Ito's colour-blind-safe palette without its black (the front's) and with its
  // yellow, too faint on white, replaced by a purple.
  static const Rgb palette[] = {{0, 114, 178},  {213, 94, 0},   {0, 158, 115},  {204, 121, 167},
                                {230, 159, 0},  {86, 180, 233}, {117, 112, 179}, {120, 120, 120}};
  return palette[index % std::size(palette)];
}

Rgb pareto_color() { return {0, 0, 0}; }

namespace {

// Text beside data points, in scene coordinates (pixels, bottom-left origin).
class PointLabels : public vtkContextItem {
 public:
  static PointLabels* New();
  vtkTypeMacro(PointLabels, vtkContextItem)

  struct Label {
    float x = 0, y = 0;
    std::string text;
  };
  std::vector<Label> labels;

  bool Paint(vtkContext2D* painter) override {
    vtkTextProperty* text = painter->GetTextProp();
    text->SetFontSize(11);
    text->SetColor(0.25, 0.25, 0.25);
    text->SetJustificationToLeft();
    text->SetVerticalJustificationToBottom();
    text->SetBold(false);
    text->SetItalic(false);
    for (const Label& l : labels) painter->DrawString(l.x, l.y, l.text);
    return true;
  }
};
vtkStandardNewMacro(PointLabels);

void require_display() {
  const char* name = std::getenv("DISPLAY");
  if (!name || !*name)
    throw std::runtime_error(
        "drawing a plot needs an X display (this VTK renders through GLX only) and DISPLAY is not set: "
        "run under xvfb-run, or start Xvfb and set DISPLAY");
  Display* display = XOpenDisplay(nullptr);
  if (!display)
    throw std::runtime_error(std::string("drawing a plot needs an X display and DISPLAY=") + name +
                             " cannot be opened (is the X server or Xvfb running?)");
  XCloseDisplay(display);
}

void require_writable(const fs::path& png) {
  if (!png.has_filename()) throw InputError(png.string(), "cannot write the plot: not a file name");
  const fs::path dir = png.parent_path().empty() ? fs::path(".") : png.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(png.string(), "cannot write the plot: the folder " + dir.string() + " does not exist");
  if (fs::is_directory(png, ec)) throw InputError(png.string(), "cannot write the plot: a folder has that name");
}

// The drawable points of a list: finite, and positive on a log axis. Counts what it drops.
struct Filtered {
  std::vector<PlotPoint> points;
  size_t non_finite = 0, non_positive = 0;
};

Filtered filter(const std::vector<PlotPoint>& points, bool log_x, bool log_y) {
  Filtered f;
  for (const PlotPoint& p : points) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      ++f.non_finite;
    else if ((log_x && p.x <= 0) || (log_y && p.y <= 0))
      ++f.non_positive;
    else
      f.points.push_back(p);
  }
  return f;
}

// The axis range around [lo, hi] (data values), padded so markers at the ends stay inside; in
// decades on a log axis. A single value gets half a decade (log) or 10% (at least 1) either side.
std::array<double, 2> padded_range(double lo, double hi, bool log) {
  if (log) {
    double a = std::log10(lo), b = std::log10(hi);
    const double pad = b - a > 1e-9 * std::max(1.0, std::abs(a)) ? 0.06 * (b - a) : 0.5;
    return {std::pow(10.0, a - pad), std::pow(10.0, b + pad)};
  }
  if (hi - lo > 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    const double pad = 0.06 * (hi - lo);
    return {lo - pad, hi + pad};
  }
  const double pad = std::max(std::abs(lo) * 0.1, 1.0);
  return {lo - pad, hi + pad};
}

vtkSmartPointer<vtkTable> table_of(const std::vector<PlotPoint>& points) {
  vtkNew<vtkDoubleArray> xs, ys;
  xs->SetName("x");
  ys->SetName("y");
  for (const PlotPoint& p : points) {
    xs->InsertNextValue(p.x);
    ys->InsertNextValue(p.y);
  }
  auto table = vtkSmartPointer<vtkTable>::New();
  table->AddColumn(xs);
  table->AddColumn(ys);
  return table;
}

std::string plural(size_t n, const char* what) { return std::to_string(n) + " " + what + (n == 1 ? "" : "s"); }

PlotAxisMap axis_map(vtkAxis* axis, bool horizontal, double height) {
  PlotAxisMap m;
  m.log = axis->GetLogScaleActive();
  m.data_min = axis->GetUnscaledMinimum();
  m.data_max = axis->GetUnscaledMaximum();
  const float* p1 = axis->GetPoint1();
  const float* p2 = axis->GetPoint2();
  // Scene coordinates have a bottom-left origin; the image's rows run down from the top.
  m.pixel_min = horizontal ? double(p1[0]) : height - double(p1[1]);
  m.pixel_max = horizontal ? double(p2[0]) : height - double(p2[1]);
  return m;
}

// Writes `png` itself, removed again when the write fails; putting it in place whole is the
// caller's (app/common/output_files.hpp).
void write_png(vtkRenderWindow* window, const fs::path& png) {
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputConnection(grab->GetOutputPort());
  writer->SetFileName(png.c_str());
  writer->Write();
  std::error_code ec;
  if (writer->GetErrorCode() != 0 || !fs::is_regular_file(png, ec) || fs::file_size(png, ec) == 0) {
    if (fs::is_regular_file(png, ec)) fs::remove(png, ec);
    throw InputError(png.string(), "cannot write the plot (no permission, or the disk is full?)");
  }
}

}  // namespace

PlotLayout write_plot_png(const PlotSpec& spec, const fs::path& png) {
  if (spec.width == 0 || spec.height == 0) throw std::invalid_argument("write_plot_png: the plot's size is zero");
  require_writable(png);
  require_display();

  PlotLayout layout;
  layout.width = spec.width;
  layout.height = spec.height;

  // What can be drawn, and the data's extent.
  std::vector<Filtered> series;
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  auto extend = [&](const std::vector<PlotPoint>& points) {
    for (const PlotPoint& p : points) {
      x_lo = std::min(x_lo, p.x), x_hi = std::max(x_hi, p.x);
      y_lo = std::min(y_lo, p.y), y_hi = std::max(y_hi, p.y);
    }
  };
  for (const PlotSeries& s : spec.series) {
    series.push_back(filter(s.points, spec.log_x, spec.log_y));
    layout.plotted += series.back().points.size();
    layout.non_finite += series.back().non_finite;
    layout.non_positive += series.back().non_positive;
    extend(series.back().points);
  }
  Filtered front = filter(spec.pareto_front, spec.log_x, spec.log_y);
  layout.non_finite += front.non_finite;
  layout.non_positive += front.non_positive;
  extend(front.points);

  std::vector<std::string> notes;
  if (layout.plotted == 0) notes.push_back("no data to plot");
  if (layout.non_finite) notes.push_back(plural(layout.non_finite, "point") + " with a non-finite value not shown");
  if (layout.non_positive) notes.push_back(plural(layout.non_positive, "point") + " <= 0 not shown on a log axis");
  for (size_t i = 0; i < notes.size(); ++i) layout.note += (i ? "; " : "") + notes[i];

  vtkNew<vtkContextView> view;
  vtkRenderWindow* window = view->GetRenderWindow();
  window->SetOffScreenRendering(true);
  window->SetSize(int(spec.width), int(spec.height));
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);

  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetTitle(layout.note.empty() ? spec.title : spec.title + "\n(" + layout.note + ")");
  chart->GetTitleProperties()->SetFontSize(16);
  chart->SetRenderEmpty(true);  // axes and title with no plot too (the "no data" image)
  chart->SetShowLegend(true);
  chart->GetLegend()->SetInline(false);  // beside the plot area, never over the data
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);

  // Axes: fixed ranges around the points and the front, padded so markers at the ends stay inside.
  const bool empty = layout.plotted == 0 && front.points.empty();
  if (empty) x_lo = y_lo = 1.0, x_hi = y_hi = 10.0;
  const auto x_range = padded_range(x_lo, x_hi, spec.log_x);
  const auto y_range = padded_range(y_lo, y_hi, spec.log_y);
  vtkAxis* x_axis = chart->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* y_axis = chart->GetAxis(vtkAxis::LEFT);
  if (empty) {  // the chart shows only the axes its plots use, so with none: these two by hand
    chart->SetAutoAxes(false);
    chart->GetAxis(vtkAxis::TOP)->SetVisible(false);
    chart->GetAxis(vtkAxis::RIGHT)->SetVisible(false);
  }
  for (auto [axis, label, log, range] :
       {std::tuple{x_axis, spec.x_label, spec.log_x, x_range}, std::tuple{y_axis, spec.y_label, spec.log_y, y_range}}) {
    axis->SetTitle(label);
    axis->SetLogScale(log);
    axis->SetBehavior(vtkAxis::FIXED);
    axis->SetUnscaledRange(range[0], range[1]);
    axis->GetTitleProperties()->SetFontSize(14);
    axis->GetLabelProperties()->SetFontSize(12);
  }

  // The front first, so the series' markers lie over its staircase. The staircase runs up from
  // the fastest front point and right from the most accurate one to the axes' ends (the bounds
  // of the region the front dominates), so a front of one point still shows as a corner.
  std::vector<vtkSmartPointer<vtkTable>> tables;  // the plots hold their input, but keep them plainly alive
  if (!front.points.empty()) {
    std::vector<TimeError> front_te;
    for (const PlotPoint& p : front.points) front_te.push_back({p.x, p.y});
    std::sort(front_te.begin(), front_te.end(), [](const TimeError& a, const TimeError& b) { return a.time < b.time; });
    std::vector<PlotPoint> stairs = {{front_te.front().time, y_range[1], ""}};
    for (const TimeError& v : pareto_staircase(front_te)) stairs.push_back({v.time, v.error, ""});
    stairs.push_back({x_range[1], front_te.back().error, ""});
    tables.push_back(table_of(stairs));
    auto* plot = vtkPlotPoints::SafeDownCast(chart->AddPlot(vtkChart::LINE));
    plot->SetInputData(tables.back(), 0, 1);
    const Rgb c = pareto_color();
    plot->SetColor(c.r, c.g, c.b, 255);
    plot->SetMarkerStyle(vtkPlotPoints::NONE);
    plot->GetPen()->SetWidth(1.5f);
    plot->GetPen()->SetLineType(vtkPen::DASH_LINE);
    plot->SetLabel("Pareto front");
  }

  // Series: a marker style each (cycling); a line needs two points.
  const int markers[] = {vtkPlotPoints::CIRCLE, vtkPlotPoints::SQUARE, vtkPlotPoints::DIAMOND, vtkPlotPoints::CROSS,
                         vtkPlotPoints::PLUS};
  for (size_t i = 0; i < spec.series.size(); ++i) {
    if (series[i].points.empty()) continue;
    tables.push_back(table_of(series[i].points));
    const bool line = spec.series[i].line && series[i].points.size() >= 2;
    auto* plot = vtkPlotPoints::SafeDownCast(chart->AddPlot(line ? vtkChart::LINE : vtkChart::POINTS));
    plot->SetInputData(tables.back(), 0, 1);
    const Rgb c = spec.series[i].color.value_or(series_color(i));
    plot->SetColor(c.r, c.g, c.b, 255);
    plot->SetMarkerStyle(markers[i % std::size(markers)]);
    plot->SetMarkerSize(9.0f);
    plot->GetPen()->SetWidth(2.0f);
    plot->SetLabel(spec.series[i].name);
    plot->SetLegendVisibility(!spec.series[i].name.empty());
  }

  window->Render();
  if (x_axis->GetLogScaleActive() != spec.log_x || y_axis->GetLogScaleActive() != spec.log_y)
    throw std::logic_error("write_plot_png: the chart refused a log axis over a positive range");
  layout.x = axis_map(x_axis, true, spec.height);
  layout.y = axis_map(y_axis, false, spec.height);

  // Point labels, placed from the layout just read (bottom-left scene coordinates).
  vtkNew<PointLabels> labels;
  for (const Filtered& s : series)
    for (const PlotPoint& p : s.points)
      if (!p.label.empty())
        if (auto px = layout.pixel_of(p.x, p.y))
          labels->labels.push_back({float((*px)[0] + 7.0), float(double(spec.height) - (*px)[1] + 4.0), p.label});
  if (!labels->labels.empty()) {
    view->GetScene()->AddItem(labels);
    window->Render();
  }

  write_png(window, png);
  return layout;
}

// --- bench_plots ------------------------------------------------------------------------------

namespace {

// Lower-case letters, digits, '.', '_' and '-'; anything else becomes '-', runs collapsed.
std::string file_safe(const std::string& name) {
  std::string s;
  for (char ch : name) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c == '.' || c == '_')
      s += char(std::tolower(c));
    else if (s.empty() || s.back() != '-')
      s += '-';
  }
  while (!s.empty() && (s.back() == '-' || s.back() == '.')) s.pop_back();
  while (!s.empty() && (s.front() == '-' || s.front() == '.')) s.erase(s.begin());
  if (s.size() > 60) s.resize(60);
  return s.empty() ? "plot" : s;
}

// The first-appearance order of the values key gives.
template <class Point, class Key>
std::vector<std::string> in_order(const std::vector<Point>& points, Key key) {
  std::vector<std::string> out;
  for (const Point& p : points)
    if (std::find(out.begin(), out.end(), key(p)) == out.end()) out.push_back(key(p));
  return out;
}

// "WxH", or "" when the point has no image size.
std::string size_name(const BenchPoint& p) {
  return p.width && p.height ? std::to_string(p.width) + "x" + std::to_string(p.height) : "";
}

std::string config_name(const BenchPoint& p) {
  const std::string size = size_name(p);
  return p.quantity + " " + p.mode + (p.label.empty() ? "" : " (" + p.label + ")") + (size.empty() ? "" : " " + size);
}

}  // namespace

std::vector<std::pair<std::string, PlotSpec>> bench_plots(const std::vector<BenchPoint>& points) {
  std::vector<std::pair<std::string, PlotSpec>> plots;
  std::set<std::string> used;
  auto unique_name = [&](const std::string& stem) {
    std::string name = stem + ".png";
    for (int k = 2; used.count(name); ++k) name = stem + "-" + std::to_string(k) + ".png";
    used.insert(name);
    return name;
  };

  for (const std::string& dataset : in_order(points, [](const BenchPoint& p) { return p.dataset; })) {
    std::vector<BenchPoint> of_dataset;
    for (const BenchPoint& p : points)
      if (p.dataset == dataset) of_dataset.push_back(p);
    for (const std::string& quantity : in_order(of_dataset, [](const BenchPoint& p) { return p.quantity; })) {
      std::vector<BenchPoint> of_quantity;
      for (const BenchPoint& p : of_dataset)
        if (p.quantity == quantity) of_quantity.push_back(p);
      for (const std::string& size : in_order(of_quantity, size_name)) {
        std::vector<BenchPoint> rows;
        for (const BenchPoint& p : of_quantity)
          if (size_name(p) == size) rows.push_back(p);
        PlotSpec spec;
        spec.title = dataset + ": " + quantity + (size.empty() ? "" : " at " + size) + ", error against time";
        spec.x_label = "time per frame (ms): GPU timestamps; VTK mappers: wall clock";
        spec.y_label = "RMSE against the CPU reference";
        spec.log_x = spec.log_y = true;
        for (const std::string& mode : in_order(rows, [](const BenchPoint& p) { return p.mode; })) {
          PlotSeries s;
          s.name = mode;
          for (const BenchPoint& p : rows)
            if (p.mode == mode) s.points.push_back({p.gpu_ms, p.error, p.label});
          spec.series.push_back(std::move(s));
        }
        std::vector<TimeError> te;
        for (const BenchPoint& p : rows) te.push_back({p.gpu_ms, p.error});
        for (const TimeError& f : pareto_front(te)) spec.pareto_front.push_back({f.time, f.error, ""});
        plots.emplace_back(unique_name("error_vs_time_" + file_safe(dataset) + "_" + file_safe(quantity) +
                                       (size.empty() ? "" : "_" + size)),
                           std::move(spec));
      }
    }
  }

  if (!points.empty()) {
    PlotSpec spec;
    spec.title = "time per frame against cell count";
    spec.x_label = "cells";
    spec.y_label = "time per frame (ms): GPU timestamps; VTK mappers: wall clock";
    spec.log_x = spec.log_y = true;
    for (const std::string& config : in_order(points, config_name)) {
      PlotSeries s;
      s.name = config;
      s.line = true;
      for (const BenchPoint& p : points)
        if (config_name(p) == config) s.points.push_back({double(p.cells), p.gpu_ms, ""});
      std::stable_sort(s.points.begin(), s.points.end(), [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
      spec.series.push_back(std::move(s));
    }
    plots.emplace_back(unique_name("time_vs_cells"), std::move(spec));
  }
  return plots;
}

std::vector<std::pair<std::string, PlotSpec>> shading_rate_plots(const std::vector<RatePoint>& points) {
  std::vector<std::pair<std::string, PlotSpec>> plots;
  std::set<std::string> used;
  for (const std::string& dataset : in_order(points, [](const RatePoint& p) { return p.dataset; })) {
    PlotSpec spec;
    spec.title = dataset + ": FLIP against shaded samples (equal terms)";
    spec.x_label = "samples shaded per frame (pixels or texels)";
    spec.y_label = "mean FLIP against the CPU reference";
    spec.log_x = spec.log_y = true;
    size_t count = 0;
    for (const std::string& series : in_order(points, [](const RatePoint& p) { return p.series; })) {
      PlotSeries s;
      s.name = series;
      s.line = true;
      for (const RatePoint& p : points)
        if (p.dataset == dataset && p.series == series) s.points.push_back({p.samples, p.flip, p.label});
      if (s.points.empty()) continue;
      std::stable_sort(s.points.begin(), s.points.end(), [](const PlotPoint& a, const PlotPoint& b) { return a.x < b.x; });
      count += s.points.size();
      spec.series.push_back(std::move(s));
    }
    if (count < 2) continue;
    std::string name = "flip_vs_samples_" + file_safe(dataset) + ".png";
    for (int k = 2; used.count(name); ++k) name = "flip_vs_samples_" + file_safe(dataset) + "-" + std::to_string(k) + ".png";
    used.insert(name);
    plots.emplace_back(name, std::move(spec));
  }
  return plots;
}

}  // namespace prismoid::bench
