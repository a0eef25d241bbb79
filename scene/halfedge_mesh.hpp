#pragma once
// A halfedge structure over a triangle mesh, as flat arrays that a GPU pass can upload as they
// are. Htex (renderer/surface/htex/htex_layout.hpp) gives every edge of it one square texture.
//
// Ours rather than a library's. Debian 12 packages both OpenMesh (libopenmesh-dev) and CGAL
// (libcgal-dev, header-only); both are general polygon meshes with handles and property
// systems, both refuse a face that would give an edge a third face (so the split
// policy below would still be ours), and both would still need converting into the flat
// twin/edge arrays the GPU reads; CGAL is also heavy to compile on this machine, and either
// would be a new package for scripts/setup.sh. Triangles only make the structure small:
// halfedge h = 3 f + k is corner k's side of face f, so next, prev and face are arithmetic and
// only twin and edge are stored.
//
// Conventions:
//  - Face f keeps the winding of its input triangle (p0, p1, p2); halfedge 3 f + k runs from
//    p_k to p_(k+1 mod 3). next(h) = 3 f + (k + 1) mod 3, prev(h) = 3 f + (k + 2) mod 3.
//  - twin(h) is the halfedge running the other way along the same edge in the neighbouring
//    face, or kNoHalfedge on a boundary.
//  - Every edge has one id; its primary halfedge is the larger id of the pair (the only one on
//    a boundary). Htex orients an edge's texture by it.
//
// What the builder does with input that is not a clean oriented 2-manifold:
//  - A triangle naming the same point twice (a, a, b) has no area and no sensible halfedges:
//    it is dropped (counted in dropped_triangles; face_of_triangle says -1 for it). A triangle
//    with three distinct points but zero area (collinear points) is kept: it still closes the
//    surface between its neighbours.
//  - An edge shared by more than two triangles (non-manifold), or by two triangles that run
//    along it in the same direction (inconsistent orientation: one of them is flipped), is an
//    error under NonManifold::Reject (InputError naming the mesh, the edge's two points and
//    the triangles), and under NonManifold::Split (the default) it is cut open: each triangle
//    there gets its own boundary edge, so nothing is shared across it (listed in split_edges).
//  - A vertex where two fans of triangles touch (a "bowtie") is kept as it is: every edge is
//    fine, only walking around that vertex covers one fan (vertex_halfedge names one of them).
//  - A point index out of range or a point that is not finite is an InputError.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/surface_mesh.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid {

inline constexpr int32_t kNoHalfedge = -1;

enum class NonManifold { Split, Reject };

struct HalfedgeMesh {
  std::string name;
  std::vector<glm::dvec3> positions;
  std::vector<std::array<uint32_t, 3>> faces;  // the kept triangles, in input order

  // Per halfedge (3 per face).
  std::vector<int32_t> twin;         // kNoHalfedge on a boundary
  std::vector<uint32_t> edge_of;     // edge id
  // Per edge.
  std::vector<int32_t> edge_halfedge;  // the primary halfedge: max(h, twin(h))
  // Per vertex: an outgoing halfedge; where the vertex lies on a boundary, the one that starts
  // its fan (twin(prev(h)) is kNoHalfedge), so next_around covers the fan; kNoHalfedge for a
  // point no face uses.
  std::vector<int32_t> vertex_halfedge;

  // Input triangle of each face, and face of each input triangle (-1: dropped).
  std::vector<uint32_t> triangle_of_face;
  std::vector<int32_t> face_of_triangle;

  // What the builder changed (see the header comment).
  uint32_t dropped_triangles = 0;
  std::vector<std::array<uint32_t, 2>> split_edges;  // point pairs (smaller index first) cut open

  size_t face_count() const { return faces.size(); }
  size_t halfedge_count() const { return twin.size(); }
  size_t edge_count() const { return edge_halfedge.size(); }
  size_t vertex_count() const { return positions.size(); }

  static int32_t face(int32_t h) { return h / 3; }
  static int32_t next(int32_t h) { return h - h % 3 + (h % 3 + 1) % 3; }
  static int32_t prev(int32_t h) { return h - h % 3 + (h % 3 + 2) % 3; }
  static int32_t corner(int32_t h) { return h % 3; }
  uint32_t vertex(int32_t h) const { return faces[h / 3][h % 3]; }  // where h starts
  uint32_t target(int32_t h) const { return vertex(next(h)); }      // where h ends
  int32_t edge(int32_t h) const { return static_cast<int32_t>(edge_of[h]); }
  bool boundary(int32_t h) const { return twin[h] == kNoHalfedge; }
  bool primary(int32_t h) const { return twin[h] < h; }  // true on a boundary
  // The next outgoing halfedge around h's start vertex (the face after h's, turning the same
  // way as the faces' winding), or kNoHalfedge when h's twin is missing.
  int32_t next_around(int32_t h) const { return twin[h] == kNoHalfedge ? kNoHalfedge : next(twin[h]); }
};

// Builds the halfedge structure of a triangle mesh (see the header comment for what happens to
// degenerate, non-manifold and inconsistently oriented input). `name` names the mesh in errors.
HalfedgeMesh build_halfedge_mesh(const std::string& name, const std::vector<glm::dvec3>& positions,
                                 const std::vector<std::array<uint32_t, 3>>& triangles,
                                 NonManifold policy = NonManifold::Split);
HalfedgeMesh build_halfedge_mesh(const SurfaceMesh& mesh, NonManifold policy = NonManifold::Split);
HalfedgeMesh build_halfedge_mesh(const SceneMesh& mesh, NonManifold policy = NonManifold::Split);

// Centroid of face f: the point the face's three halfedge triangles (and Htex's quads) share.
glm::dvec3 face_center(const HalfedgeMesh& mesh, uint32_t f);

}  // namespace prismoid
