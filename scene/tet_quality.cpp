#include "scene/tet_mesh.hpp"
#include "scene/tet_quality.hpp"

#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace prismoid {

bool is_flat(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const glm::dvec3 u = b - a, v = c - a, w = d - a;
  const double bound = 64.0 * std::numeric_limits<double>::epsilon() * glm::length(u) * glm::length(v) * glm::length(w);
  return std::abs(glm::dot(u, glm::cross(v, w))) <= bound;
}

TetQuality tet_quality(const TetMesh& mesh) {
  TetQuality q;
  for (const auto& t : mesh.tets) {
    const auto& a = mesh.points[t[0]];
    const auto& b = mesh.points[t[1]];
    const auto& c = mesh.points[t[2]];
    const auto& d = mesh.points[t[3]];
    const double v = signed_volume(a, b, c, d);
    q.total_volume += std::abs(v);
    if (is_flat(a, b, c, d)) ++q.zero_volume;
    else if (v < 0.0) ++q.inverted;
  }
  return q;
}

}  // namespace prismoid
