#pragma once
// Exact orientation of four points: the one geometric predicate the visibility order rests on.
#include <glm/vec3.hpp>

namespace prismoid::volume {

// Sign (+1, 0 or -1) of det[b - a, c - a, d - a], i.e. of six times the signed volume of
// abcd: positive when d lies on the side of the plane abc that (b - a) x (c - a) points to.
// Exact, not merely careful: a floating-point evaluation with a forward error bound decides
// unless the result is within that bound of zero; then the determinant is summed exactly in
// expansion arithmetic. So orient3d_sign of a permutation of the points is exactly the
// permutation's sign times the original, which is what keeps both cells of a face agreeing.
// Valid while the products of three coordinate differences neither overflow nor underflow
// (coordinates between about 1e-90 and 1e90 in magnitude, or zero).
int orient3d_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d);

}  // namespace prismoid::volume
