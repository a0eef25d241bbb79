#pragma once
// Orientation and degeneracy of a mesh's tetrahedra, for reports (the renderer handles both).
#include <cstddef>

#include "scene/tet_mesh_fwd.hpp"

namespace prismoid {

struct TetQuality {
  size_t zero_volume = 0;  // flat within rounding: they contribute nothing to any integral
  size_t inverted = 0;     // negative orientation (signed_volume < 0), not flat
  double total_volume = 0.0;  // sum of |volume|
};

// Whether the tetrahedron's volume is indistinguishable from zero in double precision: the
// triple product of its edge vectors u, v, w is within its rounding error. That error is below
// 64 eps |u||v||w| (six products of three terms, each |term| <= the Hadamard bound, plus the
// rounding of the differences themselves), so anything smaller carries no sign.
bool is_flat(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

TetQuality tet_quality(const TetMesh& mesh);

}  // namespace prismoid
