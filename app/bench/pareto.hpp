#pragma once
// The Pareto front of (time, error) measurements, both to be minimised. Pure: no VTK, no I/O,
// so the bench's tables and plots mark the same rows.
#include <cstddef>
#include <vector>

namespace prismoid::bench {

struct TimeError {
  double time = 0;
  double error = 0;
};

// optimal[i] is true when point i is Pareto-optimal: its time and error are finite and no other
// such point is at least as fast and at least as accurate, and strictly better in one of the two.
// Points with a non-finite time or error are never optimal and never dominate. Equal points do
// not dominate each other, so duplicates of an optimal point are all optimal.
std::vector<bool> pareto_optimal(const std::vector<TimeError>& points);

// The optimal points' values, sorted by time ascending (and so error descending), each distinct
// (time, error) once.
std::vector<TimeError> pareto_front(const std::vector<TimeError>& points);

// The front's staircase: the boundary of the region that the front dominates, as the vertices of
// a polyline. From each front point it runs at that point's error to the next point's time, then
// down to the next point's error; a front of n distinct points gives 2n - 1 vertices.
std::vector<TimeError> pareto_staircase(const std::vector<TimeError>& front);

}  // namespace prismoid::bench
