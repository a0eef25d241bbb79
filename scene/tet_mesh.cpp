#include "scene/tet_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>

#include "scene/input_error.hpp"

namespace prismoid {

namespace {
// The extents (largest axis of the bounds) whose cells double computes with (validate()):
// 2^+-300, about 2e90 and 5e-91, so that even cells a million times smaller than the data have
// volumes (products of three lengths) far inside double's normal range (2^+-1022).
constexpr double kLargestExtent = 0x1p300, kSmallestExtent = 0x1p-300;
}  // namespace

double Bounds::radius() const { return 0.5 * glm::length(max - min); }

Bounds bounds_of(const TetMesh& mesh) {
  Bounds b;
  if (mesh.points.empty()) return b;
  b.min = b.max = mesh.points.front();
  for (const auto& p : mesh.points) {
    b.min = glm::min(b.min, p);
    b.max = glm::max(b.max, p);
  }
  return b;
}

void validate(const TetMesh& mesh) {
  const std::string& src = mesh.name.empty() ? std::string("(unnamed mesh)") : mesh.name;
  if (mesh.cell_extinction.size() != mesh.tets.size())
    throw InputError(src, "has " + std::to_string(mesh.tets.size()) + " cells but " +
                              std::to_string(mesh.cell_extinction.size()) + " extinction values");
  if (!mesh.point_scalars.empty() && mesh.point_scalars.size() != mesh.points.size())
    throw InputError(src, "point scalar array has " + std::to_string(mesh.point_scalars.size()) + " values for " +
                              std::to_string(mesh.points.size()) + " points");
  if (!mesh.cell_scalars.empty() && mesh.cell_scalars.size() != mesh.tets.size())
    throw InputError(src, "cell scalar array has " + std::to_string(mesh.cell_scalars.size()) + " values for " +
                              std::to_string(mesh.tets.size()) + " cells");
  for (const auto* field : {&mesh.point_scalars, &mesh.cell_scalars})
    for (size_t i = 0; i < field->size(); ++i)
      if (!std::isfinite((*field)[i]))
        throw InputError(src, std::string(field == &mesh.point_scalars ? "point " : "cell ") + std::to_string(i) +
                                  " has a non-finite scalar value");
  if (mesh.linear_extinction()) {
    if (mesh.point_extinction.size() != mesh.points.size())
      throw InputError(src, "has " + std::to_string(mesh.points.size()) + " points but " +
                                std::to_string(mesh.point_extinction.size()) + " point extinction values");
    for (size_t i = 0; i < mesh.point_extinction.size(); ++i) {
      const double s = mesh.point_extinction[i];
      if (!std::isfinite(s) || s < 0.0)
        throw InputError(src, "point " + std::to_string(i) + " has extinction " + std::to_string(s) + " (must be finite and >= 0)");
    }
  }
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    const auto& p = mesh.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(src, "point " + std::to_string(i) + " has a non-finite coordinate");
  }
  // The cells' geometry is computed in double (volumes and orientations are products of three
  // edge lengths, squared distances of two): data whose extent, for all the renderer's own
  // math being relative to it, leaves double's range there are refused. Scaled copies of a grid
  // render alike from 1e-90 to 1e90 (tests/volume/test_scaled_copies.cpp).
  if (!mesh.points.empty() && !mesh.tets.empty()) {
    glm::dvec3 lo = mesh.points.front(), hi = lo;
    for (const auto& p : mesh.points) {
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    if (extent > kLargestExtent || (extent > 0.0 && extent < kSmallestExtent)) {
      char buf[160];
      std::snprintf(buf, sizeof buf, "its points span %.3g; the cells' geometry (volumes are products of three lengths, in "
                                     "double) holds data spanning %.1e to %.1e: rescale the coordinates",
                    extent, kSmallestExtent, kLargestExtent);
      throw InputError(src, buf);
    }
  }
  for (size_t c = 0; c < mesh.tets.size(); ++c) {
    for (uint32_t v : mesh.tets[c])
      if (v >= mesh.points.size())
        throw InputError(src, "cell " + std::to_string(c) + " refers to point " + std::to_string(v) + " but there are " +
                                  std::to_string(mesh.points.size()) + " points");
    double s = mesh.cell_extinction[c];
    if (!std::isfinite(s) || s < 0.0)
      throw InputError(src, "cell " + std::to_string(c) + " has extinction " + std::to_string(s) + " (must be finite and >= 0)");
  }
}

double signed_volume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  return glm::dot(b - a, glm::cross(c - a, d - a)) / 6.0;
}

}  // namespace prismoid
