#pragma once
// A tetrahedral volume as plain data: what io produces and the volume renderer consumes.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/bounds.hpp"

namespace prismoid {

struct TetMesh {
  std::string name;
  std::vector<glm::dvec3> points;
  std::vector<std::array<uint32_t, 4>> tets;
  std::vector<double> cell_extinction;   // sigma per cell, in 1/length units; >= 0
  // Optional sigma per point. When present, sigma is linear in each cell (interpolated from its
  // four points) and cell_extinction holds each cell's mean, for display and statistics only.
  std::vector<double> point_extinction;
  // The scalar field a transfer function maps to colour and extinction (emission-absorption):
  // per point (linear in each cell) when point_scalars is filled, else per cell. Both may be empty.
  std::vector<double> point_scalars;
  std::vector<double> cell_scalars;
  bool linear_extinction() const { return !point_extinction.empty(); }
};

Bounds bounds_of(const TetMesh& mesh);

// Throws InputError(mesh.name, ...) naming the first problem: indices out of range,
// non-finite coordinates, negative or non-finite extinction, array sizes that disagree.
void validate(const TetMesh& mesh);

// Signed volume of a tetrahedron (positive when (b-a, c-a, d-a) is right-handed).
double signed_volume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

}  // namespace prismoid
