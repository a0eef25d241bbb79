// The bench's Pareto front on hand-worked point sets.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "app/bench/pareto.hpp"

using prismoid::bench::pareto_front;
using prismoid::bench::pareto_optimal;
using prismoid::bench::pareto_staircase;
using prismoid::bench::TimeError;

namespace {

std::vector<bool> flags(std::initializer_list<int> v) {
  std::vector<bool> out;
  for (int b : v) out.push_back(b != 0);
  return out;
}

void expect_points(const std::vector<TimeError>& got, const std::vector<TimeError>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].time, want[i].time) << "vertex " << i;
    EXPECT_EQ(got[i].error, want[i].error) << "vertex " << i;
  }
}

}  // namespace

TEST(Pareto, EmptyHasNoFront) {
  EXPECT_TRUE(pareto_optimal({}).empty());
  EXPECT_TRUE(pareto_front({}).empty());
  EXPECT_TRUE(pareto_staircase({}).empty());
}

TEST(Pareto, SinglePointIsTheFront) {
  EXPECT_EQ(pareto_optimal({{3, 0.5}}), flags({1}));
  expect_points(pareto_front({{3, 0.5}}), {{3, 0.5}});
  expect_points(pareto_staircase({{3, 0.5}}), {{3, 0.5}});
}

TEST(Pareto, HandWorkedTradeOff) {
  // (1,9) fastest; (2,4) and (4,1) trade time for error; (3,5) is beaten by (2,4) in both;
  // (5,1) ties (4,1)'s error but is slower; (6,0.5) is the most accurate.
  const std::vector<TimeError> pts = {{3, 5}, {1, 9}, {4, 1}, {2, 4}, {5, 1}, {6, 0.5}};
  EXPECT_EQ(pareto_optimal(pts), flags({0, 1, 1, 1, 0, 1}));
  expect_points(pareto_front(pts), {{1, 9}, {2, 4}, {4, 1}, {6, 0.5}});
  // Staircase: along each front point's error to the next one's time, then down.
  expect_points(pareto_staircase(pareto_front(pts)),
                {{1, 9}, {2, 9}, {2, 4}, {4, 4}, {4, 1}, {6, 1}, {6, 0.5}});
}

TEST(Pareto, EqualTimeKeepsOnlyTheMoreAccurate) {
  // Same time: the lower error dominates; same error: the faster dominates.
  EXPECT_EQ(pareto_optimal({{2, 3}, {2, 1}}), flags({0, 1}));
  EXPECT_EQ(pareto_optimal({{2, 1}, {1, 1}}), flags({0, 1}));
}

TEST(Pareto, DuplicatesAreAllOptimalAndOnceOnTheFront) {
  const std::vector<TimeError> pts = {{1, 2}, {1, 2}, {2, 1}, {3, 3}, {3, 3}};
  EXPECT_EQ(pareto_optimal(pts), flags({1, 1, 1, 0, 0}));
  expect_points(pareto_front(pts), {{1, 2}, {2, 1}});
}

TEST(Pareto, NonFiniteValuesAreNeitherOptimalNorDominating) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // A NaN error at the fastest time would otherwise dominate nothing yet look optimal; a -inf
  // error would dominate everything slower. Neither may take part.
  const std::vector<TimeError> pts = {{0.5, nan}, {0.7, -inf}, {1, 2}, {2, 1}, {0.1, inf}, {nan, 0.0}};
  EXPECT_EQ(pareto_optimal(pts), flags({0, 0, 1, 1, 0, 0}));
  expect_points(pareto_front(pts), {{1, 2}, {2, 1}});
  // All non-finite: no front at all.
  EXPECT_TRUE(pareto_front({{1, nan}, {2, inf}}).empty());
}

TEST(Pareto, MatchesTheDefinitionOnAGrid) {
  // Every point of a 5x5 lattice with a few holes against the definition, pair by pair.
  std::vector<TimeError> pts;
  for (int t = 0; t < 5; ++t)
    for (int e = 0; e < 5; ++e)
      if ((t * 7 + e * 3) % 4 != 0) pts.push_back({double(t), double(4 - e) + 0.1 * t});
  const std::vector<bool> got = pareto_optimal(pts);
  for (size_t i = 0; i < pts.size(); ++i) {
    bool dominated = false;
    for (const TimeError& o : pts) {
      const bool no_worse = o.time <= pts[i].time && o.error <= pts[i].error;
      const bool better = o.time < pts[i].time || o.error < pts[i].error;
      dominated = dominated || (no_worse && better);
    }
    EXPECT_EQ(got[i], !dominated) << "point " << i << " (" << pts[i].time << ", " << pts[i].error << ")";
  }
  // By hand: (0, 1) and (1, 0.1) are optimal, nothing else.
  expect_points(pareto_front(pts), {{0, 1}, {1, 0.1}});
}
