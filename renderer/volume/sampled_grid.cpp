#include "renderer/volume/sampled_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <glm/geometric.hpp>

#include "scene/input_error.hpp"

namespace prismoid::volume {

namespace {

// The voxel containing index-space point u (per axis the lower sample, clamped so the upper
// one exists) and the fractions inside it; `inside` is false outside the samples' box.
struct Voxel {
  bool inside = false;
  glm::uvec3 lo{0}, hi{0};
  glm::dvec3 t{0.0};
};

Voxel locate(const SampledGrid& grid, const glm::dvec3& p) {
  const glm::dvec3 u = (p - grid.origin) / grid.spacing;
  Voxel v;
  for (int a = 0; a < 3; ++a) {
    const double last = double(grid.dims[a] - 1);
    if (!(u[a] >= 0.0 && u[a] <= last)) return v;
    v.lo[a] = uint32_t(std::min(std::floor(u[a]), std::max(last - 1.0, 0.0)));
    v.hi[a] = std::min(v.lo[a] + 1, grid.dims[a] - 1);
    v.t[a] = u[a] - double(v.lo[a]);
  }
  v.inside = true;
  return v;
}

// The voxel's 8 samples, c[i + 2 j + 4 k] at corner (i, j, k).
std::array<double, 8> corners(const SampledGrid& grid, const Voxel& v) {
  std::array<double, 8> c{};
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        c[i + 2 * j + 4 * k] = grid.values[grid.index(i ? v.hi.x : v.lo.x, j ? v.hi.y : v.lo.y, k ? v.hi.z : v.lo.z)];
  return c;
}

double lerp(double a, double b, double t) { return a + t * (b - a); }

}  // namespace

void validate(const SampledGrid& grid) {
  if (grid.dims.x == 0 || grid.dims.y == 0 || grid.dims.z == 0) throw InputError(grid.name, "a grid needs at least one sample per axis");
  const size_t count = size_t(grid.dims.x) * grid.dims.y * grid.dims.z;
  if (grid.values.size() != count)
    throw InputError(grid.name, "has " + std::to_string(grid.values.size()) + " values for " + std::to_string(count) + " samples");
  for (int a = 0; a < 3; ++a) {
    if (!(grid.spacing[a] > 0.0) || !std::isfinite(grid.spacing[a])) throw InputError(grid.name, "the spacing must be positive and finite");
    if (!std::isfinite(grid.origin[a])) throw InputError(grid.name, "the origin must be finite");
  }
  if (!std::isfinite(grid.background)) throw InputError(grid.name, "the background value must be finite");
  for (float v : grid.values)
    if (!std::isfinite(v)) throw InputError(grid.name, "has a non-finite value");
}

Bounds bounds_of(const SampledGrid& grid) {
  return {grid.origin, grid.position(glm::dvec3(grid.dims) - 1.0)};
}

double evaluate(const SampledGrid& grid, const glm::dvec3& p) {
  const Voxel v = locate(grid, p);
  if (!v.inside) return grid.background;
  const auto c = corners(grid, v);
  const double x00 = lerp(c[0], c[1], v.t.x), x10 = lerp(c[2], c[3], v.t.x);
  const double x01 = lerp(c[4], c[5], v.t.x), x11 = lerp(c[6], c[7], v.t.x);
  return lerp(lerp(x00, x10, v.t.y), lerp(x01, x11, v.t.y), v.t.z);
}

glm::dvec3 gradient(const SampledGrid& grid, const glm::dvec3& p) {
  const Voxel v = locate(grid, p);
  if (!v.inside) return glm::dvec3(0.0);
  const auto c = corners(grid, v);
  const glm::dvec3 t = v.t;
  // d/dx: the x differences of the four x-edges, bilinear in (y, z); likewise per axis. An
  // axis with one sample has no difference (hi = lo): its derivative is 0.
  const double dx = lerp(lerp(c[1] - c[0], c[3] - c[2], t.y), lerp(c[5] - c[4], c[7] - c[6], t.y), t.z);
  const double dy = lerp(lerp(c[2] - c[0], c[3] - c[1], t.x), lerp(c[6] - c[4], c[7] - c[5], t.x), t.z);
  const double dz = lerp(lerp(c[4] - c[0], c[5] - c[1], t.x), lerp(c[6] - c[2], c[7] - c[3], t.x), t.y);
  return glm::dvec3(dx, dy, dz) / grid.spacing;
}

double gradient_bound(const SampledGrid& grid) {
  glm::dvec3 largest(0.0);
  for (uint32_t k = 0; k < grid.dims.z; ++k)
    for (uint32_t j = 0; j < grid.dims.y; ++j)
      for (uint32_t i = 0; i < grid.dims.x; ++i) {
        const double v = grid.values[grid.index(i, j, k)];
        if (i + 1 < grid.dims.x) largest.x = std::max(largest.x, std::abs(double(grid.values[grid.index(i + 1, j, k)]) - v));
        if (j + 1 < grid.dims.y) largest.y = std::max(largest.y, std::abs(double(grid.values[grid.index(i, j + 1, k)]) - v));
        if (k + 1 < grid.dims.z) largest.z = std::max(largest.z, std::abs(double(grid.values[grid.index(i, j, k + 1)]) - v));
      }
  return glm::length(largest / grid.spacing);
}

double max_abs_value(const SampledGrid& grid) {
  double m = std::abs(grid.background);
  for (float v : grid.values) m = std::max(m, double(std::abs(v)));
  return m;
}

}  // namespace prismoid::volume
