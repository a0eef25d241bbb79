// FastAtlas's per-frame packing (renderer/surface/fastatlas/atlas_packing.hpp): boxes never
// overlap and stay inside the atlas; the chosen scale is the largest candidate that fits; the
// same boxes give the same atlas whatever order they arrive in; a chart larger than the atlas
// makes the scale fall; no charts and a million charts are handled.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>

#include "renderer/surface/fastatlas/atlas_packing.hpp"

namespace prismoid {
namespace {

using fastatlas::AtlasPacking;
using fastatlas::ChartBox;
using fastatlas::PackingOptions;

std::vector<ChartBox> random_boxes(size_t n, uint32_t largest, uint32_t seed) {
  std::mt19937 rng(seed);
  // Mostly small charts and a few large ones, as a view of a scene gives (sizes ~ 1/u^2).
  std::uniform_real_distribution<double> u(0.05, 1.0);
  std::vector<ChartBox> boxes(n);
  for (size_t i = 0; i < n; ++i) {
    boxes[i].width = std::max<uint32_t>(1, uint32_t(std::min<double>(largest, 2.0 / (u(rng) * u(rng)))));
    boxes[i].height = std::max<uint32_t>(1, uint32_t(std::min<double>(largest, 2.0 / (u(rng) * u(rng)))));
    boxes[i].root = uint32_t(rng() % 1000000);
  }
  return boxes;
}

PackingOptions square_atlas(uint32_t side) {
  PackingOptions o;
  o.atlas_width = side;
  o.atlas_height = side;
  return o;
}

// Every placed box inside the atlas and no two sharing a texel (checked on an occupancy grid).
void expect_disjoint_inside(const AtlasPacking& p, const PackingOptions& o) {
  ASSERT_TRUE(p.fits);
  std::vector<uint8_t> taken(size_t(o.atlas_width) * o.atlas_height, 0);
  for (size_t i = 0; i < p.charts.size(); ++i) {
    const auto& c = p.charts[i];
    ASSERT_LE(uint64_t(c.x) + c.width, o.atlas_width) << "chart " << i;
    ASSERT_LE(uint64_t(c.y) + c.height, o.atlas_height) << "chart " << i;
    for (uint32_t y = c.y; y < c.y + c.height; ++y)
      for (uint32_t x = c.x; x < c.x + c.width; ++x) {
        uint8_t& t = taken[size_t(y) * o.atlas_width + x];
        ASSERT_EQ(t, 0) << "chart " << i << " overlaps another at texel (" << x << ", " << y << ")";
        t = 1;
      }
  }
}

TEST(FastAtlasPacking, BoxesAreDisjointInsideTheAtlasAndKeepTheirScaledSize) {
  const PackingOptions o = square_atlas(1024);
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    const auto boxes = random_boxes(3000, 300, seed);
    const AtlasPacking p = fastatlas::pack_atlas(boxes, o);
    expect_disjoint_inside(p, o);
    for (size_t i = 0; i < boxes.size(); ++i) {
      // Each box holds its chart at the chosen scale, rounded up, plus the border; turned when wider than tall.
      const auto& c = p.charts[i];
      const uint32_t w = c.turned ? boxes[i].height : boxes[i].width, h = c.turned ? boxes[i].width : boxes[i].height;
      EXPECT_GE(double(c.width - o.border), double(w) * p.scale - 1e-9);
      EXPECT_GE(double(c.height - o.border), double(h) * p.scale - 1e-9);
      EXPECT_GE(c.height, c.width);
    }
  }
}

TEST(FastAtlasPacking, TheChosenScaleIsTheLargestCandidateThatFits) {
  const PackingOptions o = square_atlas(512);
  const auto boxes = random_boxes(2000, 200, 7);
  const AtlasPacking p = fastatlas::pack_atlas(boxes, o);
  ASSERT_TRUE(p.fits);
  ASSERT_GT(p.candidate, 0u) << "this set should not fit at scale 1 (the test would not test the choice)";
  const auto scales = fastatlas::candidate_scales(o);
  ASSERT_EQ(scales.size(), 64u);
  EXPECT_DOUBLE_EQ(p.scale, scales[p.candidate]);
  const auto order = fastatlas::packing_order(boxes);
  for (uint32_t k = 0; k < p.candidate; ++k)
    EXPECT_FALSE(fastatlas::pack_at_scale(boxes, order, scales[k], o).fits) << "candidate " << k << " fits but was not chosen";
  for (uint32_t k = 1; k < scales.size(); ++k) EXPECT_LT(scales[k], scales[k - 1]);
  EXPECT_DOUBLE_EQ(scales.front(), o.largest_scale);
  EXPECT_NEAR(scales.back(), o.smallest_scale, 1e-15);
}

TEST(FastAtlasPacking, TheSameBoxesGiveTheSameAtlasInAnyArrivalOrder) {
  const PackingOptions o = square_atlas(1024);
  const auto boxes = random_boxes(5000, 250, 11);
  const AtlasPacking a = fastatlas::pack_atlas(boxes, o);
  const AtlasPacking again = fastatlas::pack_atlas(boxes, o);
  // A permutation of the same charts (as threads might deliver them): each chart, found by its
  // root, lands where it did.
  std::vector<size_t> perm(boxes.size());
  for (size_t i = 0; i < perm.size(); ++i) perm[i] = i;
  std::shuffle(perm.begin(), perm.end(), std::mt19937(3));
  std::vector<ChartBox> shuffled(boxes.size());
  for (size_t i = 0; i < perm.size(); ++i) shuffled[i] = boxes[perm[i]];
  // Roots are the tie-break: make them unique, as a chart's lowest triangle index is.
  std::vector<ChartBox> unique = boxes;
  for (size_t i = 0; i < unique.size(); ++i) unique[i].root = uint32_t(i * 7919 % 1000003);
  for (size_t i = 0; i < perm.size(); ++i) shuffled[i] = unique[perm[i]];
  const AtlasPacking u = fastatlas::pack_atlas(unique, o);
  const AtlasPacking s = fastatlas::pack_atlas(shuffled, o);
  ASSERT_EQ(a.candidate, again.candidate);
  for (size_t i = 0; i < boxes.size(); ++i) {
    EXPECT_EQ(a.charts[i].x, again.charts[i].x);
    EXPECT_EQ(a.charts[i].y, again.charts[i].y);
  }
  ASSERT_EQ(u.candidate, s.candidate);
  for (size_t i = 0; i < perm.size(); ++i) {
    EXPECT_EQ(s.charts[i].x, u.charts[perm[i]].x) << "chart " << perm[i];
    EXPECT_EQ(s.charts[i].y, u.charts[perm[i]].y) << "chart " << perm[i];
    EXPECT_EQ(s.charts[i].turned, u.charts[perm[i]].turned);
  }
}

TEST(FastAtlasPacking, AChartLargerThanTheAtlasMakesTheScaleFall) {
  const PackingOptions o = square_atlas(256);
  std::vector<ChartBox> boxes = {{1000, 600, 5}, {10, 10, 1}, {30, 4, 2}};
  const AtlasPacking p = fastatlas::pack_atlas(boxes, o);
  expect_disjoint_inside(p, o);
  EXPECT_LT(p.scale, 256.0 / 1000.0 + 1e-12);
  EXPECT_TRUE(p.charts[0].turned);  // wider than tall: turned
  // One texel per pixel when everything fits.
  const AtlasPacking small = fastatlas::pack_atlas({{10, 20, 0}, {3, 3, 1}}, o);
  EXPECT_EQ(small.candidate, 0u);
  EXPECT_DOUBLE_EQ(small.scale, 1.0);
  // Nothing fits at the smallest scale: said, not a wrong atlas.
  PackingOptions tiny = o;
  tiny.smallest_scale = 0.5;
  const AtlasPacking none = fastatlas::pack_atlas({{5000, 5000, 0}}, tiny);
  EXPECT_FALSE(none.fits);
  EXPECT_TRUE(none.charts.empty());
}

TEST(FastAtlasPacking, NoChartsAndAMillionCharts) {
  PackingOptions o;
  const AtlasPacking empty = fastatlas::pack_atlas({}, o);
  EXPECT_TRUE(empty.fits);
  EXPECT_EQ(empty.candidate, 0u);
  EXPECT_TRUE(empty.charts.empty());
  // 10^6 one-triangle charts of a few pixels each (a 1080p frame of a dense mesh) in an 8K atlas.
  std::vector<ChartBox> many(1000000);
  std::mt19937 rng(5);
  for (size_t i = 0; i < many.size(); ++i) many[i] = {1 + uint32_t(rng() % 4), 1 + uint32_t(rng() % 4), uint32_t(i)};
  const AtlasPacking p = fastatlas::pack_atlas(many, o);
  ASSERT_TRUE(p.fits);
  EXPECT_EQ(p.candidate, 0u);
  uint64_t area = 0;
  for (const auto& c : p.charts) area += uint64_t(c.width) * c.height;
  EXPECT_LE(p.height_used, o.atlas_height);
  EXPECT_GT(double(area) / (double(o.atlas_width) * p.height_used), 0.9) << "rows of small charts should pack densely";
}

TEST(FastAtlasPacking, BadOptionsAreRefused) {
  PackingOptions o;
  o.atlas_width = 1000;
  EXPECT_THROW(fastatlas::pack_atlas({{1, 1, 0}}, o), std::invalid_argument);
  o.atlas_width = 1024;
  EXPECT_THROW(fastatlas::pack_atlas({{0, 1, 0}}, o), std::invalid_argument);
  o.smallest_scale = 2.0;
  EXPECT_THROW(fastatlas::pack_atlas({{1, 1, 0}}, o), std::invalid_argument);
}

}  // namespace
}  // namespace prismoid
