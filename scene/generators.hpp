#pragma once
// Tetrahedral meshes made in code: the embedded default dataset and analytic test volumes.
#include <cstdint>
#include <functional>

#include "scene/surface_mesh.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid {

// The axis-aligned box [lo, hi] split into n^3 cubes of 6 tetrahedra each (Kuhn split, so
// neighbouring cubes share faces exactly). Extinction per cell = sigma(cell centroid);
// point scalars = sigma at the points.
TetMesh make_box_mesh(const glm::dvec3& lo, const glm::dvec3& hi, uint32_t n,
                      const std::function<double(const glm::dvec3&)>& sigma);

// The sphere of radius r about `center` as an icosphere: an icosahedron whose faces are split
// `subdivisions` times into 4, new vertices pushed onto the sphere (20 * 4^subdivisions
// triangles, closed; winding not guaranteed consistent in orientation).
SurfaceMesh make_icosphere(const glm::dvec3& center, double radius, uint32_t subdivisions);

// The surface of the axis-aligned cube [center - half, center + half]^3, each face split into an
// n x n grid of squares and each square into two triangles (12 n^2 triangles), points shared
// along the cube's edges (closed, a 2-manifold), every triangle wound to face outwards.
SurfaceMesh make_cube_surface(const glm::dvec3& center, double half, uint32_t n);

// A ball of radius r about `center`: the convex polyhedron of an icosphere (an icosahedron
// whose faces are split `subdivisions` times into 4, vertices pushed onto the sphere), filled
// with one tetrahedron per boundary triangle joined to the centre. Extinction sigma per cell.
TetMesh make_ball_mesh(const glm::dvec3& center, double radius, uint32_t subdivisions, double sigma);

// The embedded default dataset: three Gaussian blobs of absorbing medium in [-1, 1]^3.
TetMesh make_default_volume();

}  // namespace prismoid
