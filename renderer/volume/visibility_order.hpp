#pragma once
// Exact visibility ordering of tetrahedral meshes on the CPU (a topological sort over face
// adjacency in the manner of Williams' MPVONC, 1992), for compositing cells front to back.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::volume {

// The face of a cell opposite its vertex i, as local vertex indices, ordered so that
// (q - p) x (r - p) points out of a positively oriented cell (orient3d_sign(v0, v1, v2, v3) > 0).
inline constexpr int kFaceVertices[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// Face adjacency: neighbour[c][i] is the cell across the face opposite vertex i of cell c, or -1
// on the boundary. Faces are matched by their sorted point-index triples, so the mesh must share
// points between neighbours (as .vtu files and our generators do).
//
// convex_boundary: the boundary is one closed, edge-manifold surface (every boundary edge
// joins exactly two boundary faces, consistently oriented), all of one connected piece, and it
// bends outwards or stays flat at every edge. For such a surface that means the mesh fills a
// convex region. Flat (coplanar) neighbouring faces are convex: a box split into triangles is
// a convex box. "Flat" has a tolerance: a face's neighbour may rise above its plane by up to
// 1e-6 of the bounding-box diagonal, since meshes stored in float32 (most .vtu files) carry
// relative rounding of about 6e-8 in every coordinate, and the GPU renders in float32 anyway; a
// dent that shallow cannot change an image. Meshes with cavities, separate pieces, pinched
// edges or a cell of zero volume on the boundary are reported not convex.
struct TetAdjacency {
  std::vector<std::array<int32_t, 4>> neighbour;
  size_t boundary_faces = 0;
  bool convex_boundary = false;
};

// Expected O(cells) time (a counting sort of faces by their smallest point index; the boundary
// test is a hash over boundary edges). Throws InputError(mesh.name, ...) for a face shared by
// more than two cells (naming the face's points), a cell that repeats a point, or more cells
// than int32 indices can name. The mesh must index its points in range (validate() checks).
TetAdjacency build_adjacency(const TetMesh& mesh);

struct VisibilityOrder {
  std::vector<uint32_t> front_to_back;  // every cell exactly once
  bool acyclic = true;                  // false when the 'in front of' relation had a cycle
  size_t cells_in_cycles = 0;           // cells placed by the fallback
  bool exact = false;                   // acyclic && convex_boundary: the order is exact for every ray
};

// Front-to-back order of the cells as seen from `eye`. For each interior face between cells A and
// B, A precedes B when the eye lies strictly on A's side of the face's plane (decided by the exact
// predicate orient3d_sign); an eye in the plane sees no ray cross the face, so that face adds no
// constraint. Cells wholly behind the eye are ordered too (the near plane clips them later). Among
// the cells whose predecessors are all placed, the one whose centroid is nearest the eye (to a
// relative 2^-20, ties by index, so the result is deterministic) goes first, which gives non-convex
// meshes a sensible order across their gaps (about which the adjacency says nothing, so there the
// order is approximate and `exact` is false). A cycle in the relation (possible for non-Delaunay
// meshes) is broken by placing each strongly connected set of cells as a block, its cells by
// centroid distance, once everything outside that leads into it is placed; cells_in_cycles counts
// the cells of those sets. A cell of zero volume has no side, so its own faces add no constraints.
// O(cells log cells) time; throws std::invalid_argument when `adjacency` is not the mesh's.
VisibilityOrder exact_order(const TetMesh& mesh, const TetAdjacency& adjacency, const glm::dvec3& eye);

}  // namespace prismoid::volume
