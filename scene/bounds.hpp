#pragma once
// An axis-aligned box in world space, in double precision: what framing a camera needs.
#include <glm/vec3.hpp>

namespace prismoid {

struct Bounds {
  glm::dvec3 min{0.0};
  glm::dvec3 max{0.0};
  glm::dvec3 center() const { return 0.5 * (min + max); }
  double radius() const;  // half the diagonal
};

}  // namespace prismoid
