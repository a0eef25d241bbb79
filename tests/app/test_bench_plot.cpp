// The bench's plots: VTK charts written as PNG, read back with stb_image. Markers of a colour no
// other part of the chart uses are found in the image as blobs, and their centres are compared
// with where the chart's axes (read back after rendering) map their data. Needs an X display
// (the suite runs under xvfb-run).
#include <gtest/gtest.h>

#include <stb/stb_image.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>

#include "app/bench/bench_plot.hpp"
#include "scene/input_error.hpp"

namespace fs = std::filesystem;
using namespace prismoid::bench;

namespace {

constexpr Rgb kMagenta{255, 0, 255};
constexpr Rgb kCyan{0, 200, 200};

struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  const uint8_t* at(int x, int y) const { return &rgb[(size_t(y) * size_t(width) + size_t(x)) * 3]; }
};

Image read_png(const fs::path& path) {
  Image img;
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &img.width, &img.height, &channels, 3);
  if (!data) return img;
  img.rgb.assign(data, data + size_t(img.width) * size_t(img.height) * 3);
  stbi_image_free(data);
  return img;
}

bool near_colour(const uint8_t* p, Rgb c, int tol) {
  return std::abs(int(p[0]) - c.r) <= tol && std::abs(int(p[1]) - c.g) <= tol && std::abs(int(p[2]) - c.b) <= tol;
}

struct Rect {
  int x0, y0, x1, y1;  // inclusive-exclusive pixel bounds
};

// The plot area of a layout (the axes' extent), in pixels.
Rect plot_area(const PlotLayout& l) {
  return {int(std::floor(std::min(l.x.pixel_min, l.x.pixel_max))), int(std::floor(std::min(l.y.pixel_min, l.y.pixel_max))),
          int(std::ceil(std::max(l.x.pixel_min, l.x.pixel_max))), int(std::ceil(std::max(l.y.pixel_min, l.y.pixel_max)))};
}

struct Blob {
  double x = 0, y = 0;  // centre, in pixel coordinates (pixel centres at +0.5)
  size_t pixels = 0;
};

// Connected regions (4-neighbours) of pixels within tol of c inside r, largest first.
std::vector<Blob> blobs(const Image& img, Rgb c, int tol, Rect r) {
  std::vector<uint8_t> seen(size_t(img.width) * size_t(img.height), 0);
  std::vector<Blob> out;
  for (int y = std::max(r.y0, 0); y < std::min(r.y1, img.height); ++y)
    for (int x = std::max(r.x0, 0); x < std::min(r.x1, img.width); ++x) {
      if (seen[size_t(y) * size_t(img.width) + size_t(x)] || !near_colour(img.at(x, y), c, tol)) continue;
      Blob b;
      double sx = 0, sy = 0;
      std::vector<std::pair<int, int>> stack = {{x, y}};
      seen[size_t(y) * size_t(img.width) + size_t(x)] = 1;
      while (!stack.empty()) {
        auto [px, py] = stack.back();
        stack.pop_back();
        sx += px + 0.5, sy += py + 0.5, ++b.pixels;
        const int nx[] = {px + 1, px - 1, px, px}, ny[] = {py, py, py + 1, py - 1};
        for (int k = 0; k < 4; ++k) {
          if (nx[k] < r.x0 || ny[k] < r.y0 || nx[k] >= r.x1 || ny[k] >= r.y1) continue;
          if (nx[k] < 0 || ny[k] < 0 || nx[k] >= img.width || ny[k] >= img.height) continue;
          uint8_t& s = seen[size_t(ny[k]) * size_t(img.width) + size_t(nx[k])];
          if (s || !near_colour(img.at(nx[k], ny[k]), c, tol)) continue;
          s = 1;
          stack.push_back({nx[k], ny[k]});
        }
      }
      b.x = sx / double(b.pixels), b.y = sy / double(b.pixels);
      out.push_back(b);
    }
  std::sort(out.begin(), out.end(), [](const Blob& a, const Blob& b) { return a.pixels > b.pixels; });
  return out;
}

// The blob nearest to (x, y).
const Blob* nearest(const std::vector<Blob>& bs, double x, double y) {
  const Blob* best = nullptr;
  for (const Blob& b : bs)
    if (!best || std::hypot(b.x - x, b.y - y) < std::hypot(best->x - x, best->y - y)) best = &b;
  return best;
}

class BenchPlot : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = fs::temp_directory_path() /
          ("prismoid-plot-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "-" +
           std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
  }
  void TearDown() override { fs::remove_all(dir); }
  fs::path dir;
};

PlotSeries series(std::string name, Rgb c, std::vector<PlotPoint> pts) {
  PlotSeries s;
  s.name = std::move(name);
  s.color = c;
  s.points = std::move(pts);
  return s;
}

}  // namespace

TEST_F(BenchPlot, WritesAPngOfTheAskedSize) {
  PlotSpec spec;
  spec.title = "size";
  spec.width = 700;
  spec.height = 410;
  spec.series = {series("a", kMagenta, {{1, 1}, {2, 3}})};
  const fs::path png = dir / "size.png";
  const PlotLayout layout = write_plot_png(spec, png);
  const Image img = read_png(png);
  EXPECT_EQ(img.width, 700);
  EXPECT_EQ(img.height, 410);
  EXPECT_EQ(layout.width, 700u);
  EXPECT_EQ(layout.height, 410u);
  EXPECT_EQ(layout.plotted, 2u);
  EXPECT_TRUE(layout.note.empty()) << layout.note;
  // Nothing but the PNG is left in the folder (the temporary file was renamed).
  size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u);
}

TEST_F(BenchPlot, MarkersLandWhereTheAxesMapThem) {
  PlotSpec spec;
  spec.title = "linear";
  spec.x_label = "x";
  spec.y_label = "y";
  const std::vector<PlotPoint> pts = {{1, 2}, {4, 7}, {9, 3}, {6, 5}};
  spec.series = {series("magenta", kMagenta, pts), series("cyan", kCyan, {{2, 6}, {8, 1}})};
  const fs::path png = dir / "linear.png";
  const PlotLayout layout = write_plot_png(spec, png);
  const Image img = read_png(png);
  ASSERT_EQ(img.width, 960);

  // The axes span a good part of the image and y grows upwards.
  EXPECT_GT(layout.x.pixel_max - layout.x.pixel_min, 0.5 * 960);
  EXPECT_GT(layout.y.pixel_min - layout.y.pixel_max, 0.5 * 640);
  EXPECT_FALSE(layout.x.log);

  const Rect area = plot_area(layout);
  const std::vector<Blob> found = blobs(img, kMagenta, 40, area);
  ASSERT_EQ(found.size(), pts.size()) << "one magenta marker per point inside the axes";
  for (const PlotPoint& p : pts) {
    const auto want = layout.pixel_of(p.x, p.y);
    ASSERT_TRUE(want);
    const Blob* b = nearest(found, (*want)[0], (*want)[1]);
    EXPECT_NEAR(b->x, (*want)[0], 2.0) << "x of (" << p.x << ", " << p.y << ")";
    EXPECT_NEAR(b->y, (*want)[1], 2.0) << "y of (" << p.x << ", " << p.y << ")";
    EXPECT_GE(b->pixels, 20u);
    // The pixel the point maps to is the series' colour.
    EXPECT_TRUE(near_colour(img.at(int((*want)[0]), int((*want)[1])), kMagenta, 40));
  }
  // Independently of the layout: the markers' centres are an affine image of the data.
  const Blob* b1 = nearest(found, layout.pixel_of(1, 2).value()[0], layout.pixel_of(1, 2).value()[1]);
  const Blob* b9 = nearest(found, layout.pixel_of(9, 3).value()[0], layout.pixel_of(9, 3).value()[1]);
  const Blob* b4 = nearest(found, layout.pixel_of(4, 7).value()[0], layout.pixel_of(4, 7).value()[1]);
  const double px_per_x = (b9->x - b1->x) / 8.0;
  EXPECT_NEAR(b4->x - b1->x, 3.0 * px_per_x, 1.5);
  const double px_per_y = (b4->y - b1->y) / 5.0;  // negative: up the image
  EXPECT_LT(px_per_y, 0.0);
  EXPECT_NEAR(b9->y - b1->y, 1.0 * px_per_y, 1.5);

  // The other series is there too, in its own colour.
  EXPECT_EQ(blobs(img, kCyan, 40, area).size(), 2u);
}

TEST_F(BenchPlot, LogAxesPlaceDecadesEvenly) {
  PlotSpec spec;
  spec.title = "log-log";
  spec.log_x = spec.log_y = true;
  const std::vector<PlotPoint> pts = {{1, 0.01}, {10, 0.1}, {100, 1}, {1000, 10}};
  spec.series = {series("decades", kMagenta, pts)};
  const fs::path png = dir / "log.png";
  const PlotLayout layout = write_plot_png(spec, png);
  EXPECT_TRUE(layout.x.log);
  EXPECT_TRUE(layout.y.log);
  const Image img = read_png(png);
  std::vector<Blob> found = blobs(img, kMagenta, 40, plot_area(layout));
  ASSERT_EQ(found.size(), 4u);
  std::sort(found.begin(), found.end(), [](const Blob& a, const Blob& b) { return a.x < b.x; });
  // Equal steps in both directions, one per decade, and a decade is a good part of the axis.
  const double dx = found[1].x - found[0].x, dy = found[1].y - found[0].y;
  EXPECT_GT(dx, 100.0);
  EXPECT_LT(dy, -80.0);
  for (size_t i = 1; i < found.size(); ++i) {
    EXPECT_NEAR(found[i].x - found[i - 1].x, dx, 1.5) << "decade " << i;
    EXPECT_NEAR(found[i].y - found[i - 1].y, dy, 1.5) << "decade " << i;
    const auto want = layout.pixel_of(pts[i].x, pts[i].y);
    EXPECT_NEAR(found[i].x, (*want)[0], 2.0);
    EXPECT_NEAR(found[i].y, (*want)[1], 2.0);
  }
  // Half a decade lands half-way: sqrt(10) between 1 and 10.
  const auto mid = layout.pixel_of(std::sqrt(10.0), 0.01);
  EXPECT_NEAR((*mid)[0], 0.5 * (found[0].x + found[1].x), 1.5);
}

TEST_F(BenchPlot, LabelsAreDrawnBesideTheirPointsOnly) {
  PlotSpec spec;
  spec.title = "labels";
  spec.series = {series("m", kMagenta, {{1, 1, "labelled point"}, {1, 9, ""}, {9, 1, ""}})};
  const PlotLayout layout = write_plot_png(spec, dir / "labels.png");
  const Image img = read_png(dir / "labels.png");
  // Grey text ink in the box to the right of and just above a point.
  auto ink_beside = [&](double x, double y) {
    const auto p = layout.pixel_of(x, y);
    size_t ink = 0;
    for (int py = int((*p)[1]) - 18; py < int((*p)[1]) - 2; ++py)
      for (int px = int((*p)[0]) + 7; px < int((*p)[0]) + 90; ++px) ink += near_colour(img.at(px, py), {64, 64, 64}, 60);
    return ink;
  };
  EXPECT_GT(ink_beside(1, 1), 30u);
  EXPECT_EQ(ink_beside(1, 9), 0u);
}

TEST_F(BenchPlot, DropsNonPositiveOnLogAxesAndNonFiniteWithANote) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  PlotSpec spec;
  spec.title = "dropped";
  spec.log_y = true;  // x linear: x = 0 and x < 0 are fine there
  spec.series = {series("m", kMagenta, {{0, 1}, {-1, 2}, {1, 0}, {2, -3}, {3, nan}, {inf, 1}, {1, 10}, {2, 100}})};
  spec.pareto_front = {{1, 10}, {5, 0}};
  const PlotLayout layout = write_plot_png(spec, dir / "dropped.png");
  EXPECT_EQ(layout.plotted, 4u);      // (0,1) (-1,2) (1,10) (2,100)
  EXPECT_EQ(layout.non_positive, 3u); // (1,0) (2,-3) and the front's (5,0)
  EXPECT_EQ(layout.non_finite, 2u);
  EXPECT_NE(layout.note.find("3 points <= 0 not shown on a log axis"), std::string::npos) << layout.note;
  EXPECT_NE(layout.note.find("2 points with a non-finite value"), std::string::npos) << layout.note;
  EXPECT_FALSE(layout.pixel_of(1, 0));
  EXPECT_FALSE(layout.pixel_of(nan, 1));
  EXPECT_TRUE(layout.pixel_of(-1, 2));
  const Image img = read_png(dir / "dropped.png");
  EXPECT_EQ(blobs(img, kMagenta, 40, plot_area(layout)).size(), 4u);
}

TEST_F(BenchPlot, ParetoFrontIsAStaircaseOverThePoints) {
  PlotSpec spec;
  spec.title = "front";
  spec.series = {series("m", kMagenta, {{1, 9}, {2, 4}, {4, 1}, {3, 6}})};
  spec.pareto_front = {{1, 9}, {2, 4}, {4, 1}};
  const PlotLayout layout = write_plot_png(spec, dir / "front.png");
  const Image img = read_png(dir / "front.png");
  auto dark = [&](double x, double y) {  // any near-black pixel within 1 px
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (near_colour(img.at(int(x) + dx, int(y) + dy), pareto_color(), 90)) return true;
    return false;
  };
  // Along each step's run (at the previous point's error, away from the markers), mostly dark:
  // the line is dashed.
  auto run_fraction = [&](double x0, double x1, double y) {
    const auto a = layout.pixel_of(x0, y), b = layout.pixel_of(x1, y);
    int hit = 0, n = 0;
    for (double x = (*a)[0] + 8; x < (*b)[0] - 8; x += 1.0, ++n) hit += dark(x, (*a)[1]);
    return double(hit) / n;
  };
  EXPECT_GT(run_fraction(1, 2, 9), 0.4);
  EXPECT_GT(run_fraction(2, 4, 4), 0.4);
  // Its rises, at the next point's time.
  auto rise_fraction = [&](double x, double y0, double y1) {
    const auto a = layout.pixel_of(x, y0), b = layout.pixel_of(x, y1);
    int hit = 0, n = 0;
    for (double y = (*b)[1] + 8; y < (*a)[1] - 8; y += 1.0, ++n) hit += dark((*a)[0], y);
    return double(hit) / n;
  };
  EXPECT_GT(rise_fraction(2, 4, 9), 0.4);
  EXPECT_GT(rise_fraction(4, 1, 4), 0.4);
  // Not a straight line between front points: nothing dark off the staircase, half-way along
  // the chord from (1, 9) to (2, 4).
  const auto chord = layout.pixel_of(1.5, 6.5);
  EXPECT_FALSE(dark((*chord)[0], (*chord)[1]));
  // The dominated point (3, 6) is drawn but not on the front.
  EXPECT_EQ(blobs(img, kMagenta, 40, plot_area(layout)).size(), 4u);
}

TEST_F(BenchPlot, EmptyPlotIsWrittenSayingNoData) {
  PlotSpec spec;
  spec.title = "empty";
  spec.log_x = true;
  spec.series = {series("nothing", kMagenta, {{std::numeric_limits<double>::quiet_NaN(), 1}})};
  const fs::path png = dir / "empty.png";
  const PlotLayout layout = write_plot_png(spec, png);
  EXPECT_EQ(layout.plotted, 0u);
  EXPECT_EQ(layout.non_finite, 1u);
  EXPECT_NE(layout.note.find("no data"), std::string::npos) << layout.note;
  const Image img = read_png(png);
  EXPECT_EQ(img.width, 960);
  EXPECT_EQ(img.height, 640);
  EXPECT_TRUE(blobs(img, kMagenta, 40, {0, 0, img.width, img.height}).empty());
  // Not a blank image: the axes span most of it, and there is ink (axes, ticks, title, note).
  EXPECT_GT(layout.x.pixel_max - layout.x.pixel_min, 0.5 * 960);
  EXPECT_GT(layout.y.pixel_min - layout.y.pixel_max, 0.5 * 640);
  size_t ink = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) ink += near_colour(img.at(x, y), {0, 0, 0}, 100);
  EXPECT_GT(ink, 1000u);
  // The x axis line is drawn along its row.
  const int axis_row = int(layout.y.pixel_min);
  size_t axis_ink = 0;
  for (int x = int(layout.x.pixel_min) + 2; x < int(layout.x.pixel_max) - 2; ++x)
    for (int dy = -1; dy <= 1; ++dy) axis_ink += near_colour(img.at(x, axis_row + dy), {0, 0, 0}, 100) ? 1 : 0;
  EXPECT_GT(axis_ink, size_t(0.9 * (layout.x.pixel_max - layout.x.pixel_min - 4)));
  // No series at all: the same.
  EXPECT_EQ(write_plot_png(PlotSpec{}, dir / "none.png").plotted, 0u);
  EXPECT_TRUE(fs::is_regular_file(dir / "none.png"));
}

TEST_F(BenchPlot, UnwritablePathIsAnInputErrorNamingIt) {
  PlotSpec spec;
  spec.series = {series("a", kMagenta, {{1, 1}})};
  const fs::path missing = dir / "no-such-folder" / "plot.png";
  try {
    write_plot_png(spec, missing);
    FAIL() << "no error for a missing folder";
  } catch (const prismoid::InputError& e) {
    EXPECT_EQ(e.source(), missing.string());
    EXPECT_NE(std::string(e.what()).find("does not exist"), std::string::npos) << e.what();
  }
  fs::create_directories(dir / "taken.png");
  try {
    write_plot_png(spec, dir / "taken.png");
    FAIL() << "no error for a folder in the way";
  } catch (const prismoid::InputError& e) {
    EXPECT_EQ(e.source(), (dir / "taken.png").string());
  }
  EXPECT_FALSE(fs::exists(missing));
}

TEST_F(BenchPlot, WithoutADisplayTheErrorSaysSo) {
  const char* display = std::getenv("DISPLAY");
  const std::string saved = display ? display : "";
  ::unsetenv("DISPLAY");
  PlotSpec spec;
  spec.series = {series("a", kMagenta, {{1, 1}})};
  try {
    write_plot_png(spec, dir / "x.png");
    ADD_FAILURE() << "no error without DISPLAY";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("DISPLAY is not set"), std::string::npos) << e.what();
  }
  // Set, but no server there.
  ::setenv("DISPLAY", ":4093", 1);
  try {
    write_plot_png(spec, dir / "x.png");
    ADD_FAILURE() << "no error for an X display that is not there";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("DISPLAY=:4093 cannot be opened"), std::string::npos) << e.what();
  }
  if (saved.empty())
    ::unsetenv("DISPLAY");
  else
    ::setenv("DISPLAY", saved.c_str(), 1);
  EXPECT_FALSE(fs::exists(dir / "x.png"));
}

// --- bench_plots: from the bench's rows to the specs --------------------------------------------

TEST(BenchPlots, OneErrorPlotPerDatasetAndQuantityAndOneScalingPlot) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<BenchPoint> rows = {
      {"ball:2", "color", "interval", "", 1000, 2.0, 0.05},
      {"ball:2", "color", "interval-sorted", "", 1000, 3.0, 0.02},
      {"ball:2", "color", "interval-sorted", "preintegration 16", 1000, 4.0, 0.03},  // dominated
      {"ball:2", "color", "interval-exact-order", "", 1000, 9.0, 0.001},
      {"ball:2", "optical-depth", "interval", "", 1000, 1.0, 1e-4},
      {"ball:2", "optical-depth", "interval", "tetlet 1", 1000, 1.5, nan},
      {"/data/My Mesh.vtu", "color", "interval", "", 50000, 20.0, 0.04},
      {"/data/My Mesh.vtu", "color", "interval-sorted", "", 50000, 30.0, 0.01},
  };
  const auto plots = bench_plots(rows);
  ASSERT_EQ(plots.size(), 4u);
  EXPECT_EQ(plots[0].first, "error_vs_time_ball-2_color.png");
  EXPECT_EQ(plots[1].first, "error_vs_time_ball-2_optical-depth.png");
  EXPECT_EQ(plots[2].first, "error_vs_time_data-my-mesh.vtu_color.png");
  EXPECT_EQ(plots[3].first, "time_vs_cells.png");

  const PlotSpec& ball = plots[0].second;
  EXPECT_TRUE(ball.log_x && ball.log_y);
  ASSERT_EQ(ball.series.size(), 3u);  // a series per mode, in order of appearance
  EXPECT_EQ(ball.series[0].name, "interval");
  EXPECT_EQ(ball.series[1].name, "interval-sorted");
  ASSERT_EQ(ball.series[1].points.size(), 2u);
  EXPECT_EQ(ball.series[1].points[1].x, 4.0);
  EXPECT_EQ(ball.series[1].points[1].y, 0.03);
  EXPECT_EQ(ball.series[1].points[1].label, "preintegration 16");
  // Front: (2, .05), (3, .02), (9, .001); (4, .03) is beaten by (3, .02).
  ASSERT_EQ(ball.pareto_front.size(), 3u);
  EXPECT_EQ(ball.pareto_front[0].x, 2.0);
  EXPECT_EQ(ball.pareto_front[1].x, 3.0);
  EXPECT_EQ(ball.pareto_front[2].x, 9.0);
  // The NaN error is on its plot (write_plot_png drops and counts it) but not on the front.
  EXPECT_EQ(plots[1].second.pareto_front.size(), 1u);

  // Scaling: a line per configuration through the datasets by cell count.
  const PlotSpec& scaling = plots[3].second;
  EXPECT_EQ(scaling.series.size(), 6u);
  EXPECT_EQ(scaling.series[0].name, "color interval");
  EXPECT_TRUE(scaling.series[0].line);
  ASSERT_EQ(scaling.series[0].points.size(), 2u);
  EXPECT_EQ(scaling.series[0].points[0].x, 1000.0);
  EXPECT_EQ(scaling.series[0].points[1].x, 50000.0);
  EXPECT_EQ(scaling.series[0].points[1].y, 20.0);
  EXPECT_EQ(scaling.series[2].name, "color interval-sorted (preintegration 16)");

  EXPECT_TRUE(bench_plots({}).empty());
}

// The equal-terms plot: per scene, a line per configuration through its rates, by samples.
TEST(BenchPlots, ShadingRatePlotsALinePerConfigurationPerScene) {
  const std::vector<RatePoint> points = {
      {"bunny 1920x1080", "fastatlas atlas=8192", "sf=1", 250000, 0.0013}, {"bunny 1920x1080", "fastatlas atlas=8192", "sf=0.5", 63000, 0.0023},
      {"bunny 1920x1080", "msa charts=perspective", "sf=1", 568000, 0.0021}, {"bunny 1920x1080", "msa charts=perspective", "sf=0.5", 97000, 0.0056},
      {"dragon 1920x1080", "fastatlas atlas=8192", "sf=1", 218000, 0.0020},  // one point: no plot
  };
  const auto plots = shading_rate_plots(points);
  ASSERT_EQ(plots.size(), 1u);
  EXPECT_EQ(plots[0].first, "flip_vs_samples_bunny-1920x1080.png");
  const PlotSpec& p = plots[0].second;
  EXPECT_TRUE(p.log_x && p.log_y);
  ASSERT_EQ(p.series.size(), 2u);
  EXPECT_EQ(p.series[0].name, "fastatlas atlas=8192");
  EXPECT_TRUE(p.series[0].line);
  ASSERT_EQ(p.series[0].points.size(), 2u);
  EXPECT_EQ(p.series[0].points[0].x, 63000.0);  // by samples
  EXPECT_EQ(p.series[0].points[0].label, "sf=0.5");
  EXPECT_EQ(p.series[1].points[1].y, 0.0021);
  EXPECT_TRUE(shading_rate_plots({}).empty());
}

TEST(BenchPlots, FileNamesStayUniqueWhenDatasetsLookAlike) {
  const std::vector<BenchPoint> rows = {{"a b", "color", "interval", "", 10, 1.0, 0.1},
                                        {"a:b", "color", "interval", "", 10, 1.0, 0.1}};
  const auto plots = bench_plots(rows);
  ASSERT_EQ(plots.size(), 3u);
  EXPECT_EQ(plots[0].first, "error_vs_time_a-b_color.png");
  EXPECT_EQ(plots[1].first, "error_vs_time_a-b_color-2.png");
}

TEST(BenchPlots, ImageSizesArePlottedApart) {
  // The same configuration at two sizes: its errors are not comparable, so two plots, each with
  // its own front, and two lines on the scaling plot.
  const std::vector<BenchPoint> rows = {{"d", "color", "interval", "", 10, 1.0, 0.1, 400, 300},
                                        {"d", "color", "interval-sorted", "", 10, 2.0, 0.05, 400, 300},
                                        {"d", "color", "interval", "", 10, 3.0, 0.2, 800, 600}};
  const auto plots = bench_plots(rows);
  ASSERT_EQ(plots.size(), 3u);
  EXPECT_EQ(plots[0].first, "error_vs_time_d_color_400x300.png");
  EXPECT_EQ(plots[1].first, "error_vs_time_d_color_800x600.png");
  EXPECT_NE(plots[1].second.title.find("at 800x600"), std::string::npos) << plots[1].second.title;
  EXPECT_EQ(plots[0].second.pareto_front.size(), 2u);
  ASSERT_EQ(plots[1].second.pareto_front.size(), 1u);
  EXPECT_EQ(plots[1].second.pareto_front[0].y, 0.2);  // would be dominated by (1, 0.1) if mixed
  ASSERT_EQ(plots[2].second.series.size(), 3u);
  EXPECT_EQ(plots[2].second.series[2].name, "color interval 800x600");
}

TEST_F(BenchPlot, BenchPlotsRenderWithLabelsAndFront) {
  const std::vector<BenchPoint> rows = {
      {"ball:2", "color", "interval", "", 1000, 2.0, 0.05},
      {"ball:2", "color", "interval-sorted", "", 1000, 3.0, 0.02},
      {"ball:2", "color", "interval-sorted", "preintegration 16", 1000, 4.0, 0.03},
      {"ball:2", "color", "interval-exact-order", "", 1000, 9.0, 0.001},
      {"big", "color", "interval", "", 80000, 40.0, 0.04},
  };
  for (const auto& [name, spec] : bench_plots(rows)) {
    const PlotLayout layout = write_plot_png(spec, dir / name);
    EXPECT_GT(layout.plotted, 0u) << name;
    EXPECT_TRUE(layout.note.empty()) << name << ": " << layout.note;
    EXPECT_EQ(read_png(dir / name).width, 960) << name;
    // Every series' colour is in the image, inside the axes.
    for (size_t i = 0; i < spec.series.size(); ++i)
      EXPECT_FALSE(blobs(read_png(dir / name), series_color(i), 30, plot_area(layout)).empty()) << name << " series " << i;
  }
}
