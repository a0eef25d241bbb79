#pragma once
// Tetrahedral meshes made in code: the embedded default dataset and analytic test volumes.
#include <cstdint>
#include <functional>

#include "scene/tet_mesh.hpp"

namespace prismoid {

// The axis-aligned box [lo, hi] split into n^3 cubes of 6 tetrahedra each (Kuhn split, so
// neighbouring cubes share faces exactly). Extinction per cell = sigma(cell centroid);
// point scalars = sigma at the points.
TetMesh make_box_mesh(const glm::dvec3& lo, const glm::dvec3& hi, uint32_t n,
                      const std::function<double(const glm::dvec3&)>& sigma);

// The embedded default dataset: three Gaussian blobs of absorbing medium in [-1, 1]^3.
TetMesh make_default_volume();

}  // namespace prismoid
