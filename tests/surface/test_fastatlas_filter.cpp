// FastAtlas's hard-edge filter (renderer/surface/fastatlas/atlas_filter.hpp): its five cases,
// each against what it must give, and which taps count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <glm/trigonometric.hpp>

#include "renderer/surface/fastatlas/atlas_filter.hpp"

namespace prismoid {
namespace {

using fastatlas::FilterTaps;

FilterTaps taps(bool a, bool b, bool c, bool d) {
  FilterTaps t;
  t.value = {glm::dvec3(0.0, 1.0, 2.0), glm::dvec3(4.0, 1.0, 0.0), glm::dvec3(8.0, 5.0, 2.0), glm::dvec3(2.0, 9.0, 6.0)};
  t.usable = {a, b, c, d};
  return t;
}

void expect_near(const glm::dvec3& got, const glm::dvec3& want) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], want[k], 1e-12) << "channel " << k;
}

TEST(FastAtlasFilter, FourTapsAreBilinear) {
  const FilterTaps t = taps(true, true, true, true);
  const glm::dvec2 at(0.25, 0.75);
  const glm::dvec3 want = 0.75 * 0.25 * t.value[0] + 0.25 * 0.25 * t.value[1] + 0.75 * 0.75 * t.value[2] + 0.25 * 0.75 * t.value[3];
  expect_near(fastatlas::hard_edge_filter(t, at), want);
}

TEST(FastAtlasFilter, ThreeTapsAreBarycentricAndClampedToTheirValues) {
  // Taps 0, 1, 2 (the lower-left triangle): inside it, the plane through the three values.
  const FilterTaps t = taps(true, true, true, false);
  const glm::dvec2 inside(0.2, 0.3);
  expect_near(fastatlas::hard_edge_filter(t, inside), 0.5 * t.value[0] + 0.2 * t.value[1] + 0.3 * t.value[2]);
  // Beyond it (toward the unusable corner) the plane would extrapolate: held to the three values.
  const glm::dvec3 far = fastatlas::hard_edge_filter(t, glm::dvec2(0.95, 0.95));
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(far[k], std::min({t.value[0][k], t.value[1][k], t.value[2][k]}));
    EXPECT_LE(far[k], std::max({t.value[0][k], t.value[1][k], t.value[2][k]}));
  }
  // Its unclamped value there leaves the range in some channel (so the clamp is what holds it).
  const glm::dvec3 plane = -0.9 * t.value[0] + 0.95 * t.value[1] + 0.95 * t.value[2];
  EXPECT_GT(plane.x, std::max({t.value[0].x, t.value[1].x, t.value[2].x}));
}

TEST(FastAtlasFilter, TwoTapsAreLinearAlongTheirLine) {
  // Neighbours along x: fx alone.
  const FilterTaps along = taps(true, true, false, false);
  expect_near(fastatlas::hard_edge_filter(along, glm::dvec2(0.3, 0.9)), 0.7 * along.value[0] + 0.3 * along.value[1]);
  // A diagonal pair: the sample projected onto the diagonal.
  const FilterTaps diagonal = taps(true, false, false, true);
  expect_near(fastatlas::hard_edge_filter(diagonal, glm::dvec2(0.2, 0.6)), 0.6 * diagonal.value[0] + 0.4 * diagonal.value[3]);
}

TEST(FastAtlasFilter, OneTapIsThatTexelAndNoneIsTheNearestHeldTexel) {
  const FilterTaps one = taps(false, false, true, false);
  expect_near(fastatlas::hard_edge_filter(one, glm::dvec2(0.9, 0.1)), one.value[2]);
  const FilterTaps none = taps(false, false, false, false);
  expect_near(fastatlas::hard_edge_filter(none, glm::dvec2(0.9, 0.1)), none.value[1]);
  expect_near(fastatlas::hard_edge_filter(none, glm::dvec2(0.2, 0.7)), none.value[2]);
  // An empty nearest texel (a triangle with no texel of its own): the first tap holding one.
  FilterTaps empty_nearest = none;
  empty_nearest.held = {false, true, false, true};
  expect_near(fastatlas::hard_edge_filter(empty_nearest, glm::dvec2(0.2, 0.7)), none.value[1]);
}

TEST(FastAtlasFilter, TapsCountForTheOwnTriangleAndGentleNeighboursOnly) {
  const glm::dvec3 up(0.0, 0.0, 1.0);
  auto tilted = [](double degrees) { return glm::dvec3(std::sin(glm::radians(degrees)), 0.0, std::cos(glm::radians(degrees))); };
  EXPECT_TRUE(fastatlas::tap_usable(true, false, up, tilted(170.0)));
  EXPECT_TRUE(fastatlas::tap_usable(false, true, up, tilted(30.0)));
  EXPECT_TRUE(fastatlas::tap_usable(false, true, up, tilted(74.0)));
  EXPECT_FALSE(fastatlas::tap_usable(false, true, up, tilted(76.0)));  // a crease: its shading is not ours
  EXPECT_FALSE(fastatlas::tap_usable(false, false, up, up));           // packed next to us, not a neighbour
}

}  // namespace
}  // namespace prismoid
