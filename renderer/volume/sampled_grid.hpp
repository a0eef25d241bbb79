#pragma once
// A scalar field sampled on a regular grid (an image volume, a dense OpenVDB grid), read back
// by trilinear interpolation: the field `interval-march` samples for real voxel data. The
// double twin of shaders/volume/grid_field.glsl.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/bounds.hpp"

namespace prismoid::volume {

struct SampledGrid {
  glm::uvec3 dims{0};           // samples per axis
  glm::dvec3 origin{0.0};       // world position of sample (0, 0, 0)
  glm::dvec3 spacing{1.0};      // world distance between neighbouring samples, per axis
  std::vector<float> values;    // dims.x * dims.y * dims.z, x fastest, then y, then z
  double background = 0.0;      // the field outside the samples' box
  std::string name = "grid";    // names the grid in errors

  size_t index(uint32_t i, uint32_t j, uint32_t k) const { return (size_t(k) * dims.y + j) * dims.x + i; }
  glm::dvec3 position(const glm::dvec3& ijk) const { return origin + ijk * spacing; }
};

// Throws InputError(grid.name, ...) for empty dims, a value count other than their product,
// non-finite or non-positive spacing, non-finite origin, values or background.
void validate(const SampledGrid& grid);

// The box of the samples: origin to origin + (dims - 1) * spacing.
Bounds bounds_of(const SampledGrid& grid);

// Trilinear interpolation of the samples at p, the background outside the samples' box (the
// box itself, faces included, is inside). Continuous inside; its gradient jumps across voxel
// faces, so it has no second-derivative bound across them.
double evaluate(const SampledGrid& grid, const glm::dvec3& p);
// The gradient of the trilinear interpolant of the voxel containing p (on a face between two
// voxels, the one on the upper side, except at the box's upper faces); zero outside.
glm::dvec3 gradient(const SampledGrid& grid, const glm::dvec3& p);

// A bound on |gradient| everywhere: each partial derivative is a convex combination of the
// differences of neighbouring samples along its axis over the spacing.
double gradient_bound(const SampledGrid& grid);
// The largest |value| of the samples and the background.
double max_abs_value(const SampledGrid& grid);

}  // namespace prismoid::volume
