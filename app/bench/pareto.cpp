#include "app/bench/pareto.hpp"

#include <algorithm>
#include <cmath>

namespace prismoid::bench {

namespace {

bool finite(const TimeError& p) { return std::isfinite(p.time) && std::isfinite(p.error); }

}  // namespace

std::vector<bool> pareto_optimal(const std::vector<TimeError>& points) {
  // Sorted by time then error, a point is optimal when its error is below the best error of every
  // strictly faster point and it is the first (lowest error) among the points of its own time.
  std::vector<size_t> order;
  for (size_t i = 0; i < points.size(); ++i)
    if (finite(points[i])) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return points[a].time != points[b].time ? points[a].time < points[b].time : points[a].error < points[b].error;
  });
  std::vector<bool> optimal(points.size(), false);
  double best_faster = INFINITY;  // the lowest error among points strictly faster than the current group
  for (size_t g = 0; g < order.size();) {
    size_t end = g;
    while (end < order.size() && points[order[end]].time == points[order[g]].time) ++end;
    const double group_best = points[order[g]].error;
    if (group_best < best_faster)
      for (size_t k = g; k < end && points[order[k]].error == group_best; ++k) optimal[order[k]] = true;
    best_faster = std::min(best_faster, group_best);
    g = end;
  }
  return optimal;
}

std::vector<TimeError> pareto_front(const std::vector<TimeError>& points) {
  const std::vector<bool> optimal = pareto_optimal(points);
  std::vector<TimeError> front;
  for (size_t i = 0; i < points.size(); ++i)
    if (optimal[i]) front.push_back(points[i]);
  std::sort(front.begin(), front.end(), [](const TimeError& a, const TimeError& b) { return a.time < b.time; });
  front.erase(std::unique(front.begin(), front.end(),
                          [](const TimeError& a, const TimeError& b) { return a.time == b.time && a.error == b.error; }),
              front.end());
  return front;
}

std::vector<TimeError> pareto_staircase(const std::vector<TimeError>& front) {
  std::vector<TimeError> stairs;
  for (size_t i = 0; i < front.size(); ++i) {
    if (i > 0) stairs.push_back({front[i].time, front[i - 1].error});
    stairs.push_back(front[i]);
  }
  return stairs;
}

}  // namespace prismoid::bench
