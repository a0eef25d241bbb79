#include "scene/halfedge_mesh.hpp"

#include <cmath>
#include <limits>
#include <set>
#include <string>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "support/test_meshes.hpp"

namespace prismoid {
namespace {

// Every invariant a halfedge structure must keep, whatever the input.
void expect_invariants(const HalfedgeMesh& m) {
  const auto hn = static_cast<int32_t>(m.halfedge_count());
  ASSERT_EQ(m.halfedge_count(), 3 * m.face_count());
  ASSERT_EQ(m.edge_of.size(), m.halfedge_count());
  std::vector<int> per_edge(m.edge_count(), 0);
  for (int32_t h = 0; h < hn; ++h) {
    EXPECT_EQ(HalfedgeMesh::next(HalfedgeMesh::next(HalfedgeMesh::next(h))), h);
    EXPECT_EQ(HalfedgeMesh::prev(HalfedgeMesh::next(h)), h);
    EXPECT_EQ(HalfedgeMesh::face(HalfedgeMesh::next(h)), HalfedgeMesh::face(h));
    EXPECT_EQ(m.vertex(h), m.faces[h / 3][h % 3]);
    EXPECT_EQ(m.target(h), m.vertex(HalfedgeMesh::next(h)));
    EXPECT_NE(m.vertex(h), m.target(h));
    const int32_t t = m.twin[h];
    if (t != kNoHalfedge) {
      ASSERT_GE(t, 0);
      ASSERT_LT(t, hn);
      EXPECT_NE(t, h);
      EXPECT_EQ(m.twin[t], h);
      EXPECT_EQ(m.vertex(t), m.target(h));
      EXPECT_EQ(m.target(t), m.vertex(h));
      EXPECT_NE(HalfedgeMesh::face(t), HalfedgeMesh::face(h));
      EXPECT_EQ(m.edge_of[t], m.edge_of[h]);
    }
    ASSERT_LT(m.edge_of[h], m.edge_count());
    ++per_edge[m.edge_of[h]];
    EXPECT_EQ(m.edge_halfedge[m.edge_of[h]], std::max(h, t));
    EXPECT_EQ(m.primary(h), h == m.edge_halfedge[m.edge_of[h]]);
  }
  for (size_t e = 0; e < m.edge_count(); ++e) {
    EXPECT_GE(per_edge[e], 1);
    EXPECT_LE(per_edge[e], 2);
    EXPECT_EQ(per_edge[e] == 1, m.boundary(m.edge_halfedge[e])) << "edge " << e;
  }
  // Faces <-> input triangles.
  for (size_t f = 0; f < m.face_count(); ++f) EXPECT_EQ(m.face_of_triangle[m.triangle_of_face[f]], int32_t(f));
}

// Walks around vertex v from vertex_halfedge; returns the outgoing halfedges met (one fan).
std::vector<int32_t> fan(const HalfedgeMesh& m, uint32_t v) {
  std::vector<int32_t> out;
  int32_t h = m.vertex_halfedge[v];
  while (h != kNoHalfedge) {
    out.push_back(h);
    h = m.next_around(h);
    if (h == m.vertex_halfedge[v] || out.size() > m.halfedge_count()) break;
  }
  return out;
}

// For a 2-manifold (also at vertices): the fan from vertex_halfedge holds every outgoing
// halfedge of the vertex once, and ends on a boundary halfedge exactly when the vertex is on the
// boundary.
void expect_vertex_fans(const HalfedgeMesh& m) {
  std::vector<std::vector<int32_t>> outgoing(m.vertex_count());
  for (int32_t h = 0; h < int32_t(m.halfedge_count()); ++h) outgoing[m.vertex(h)].push_back(h);
  for (uint32_t v = 0; v < m.vertex_count(); ++v) {
    if (outgoing[v].empty()) {
      EXPECT_EQ(m.vertex_halfedge[v], kNoHalfedge);
      continue;
    }
    const std::vector<int32_t> ring = fan(m, v);
    const std::set<int32_t> met(ring.begin(), ring.end()), all(outgoing[v].begin(), outgoing[v].end());
    EXPECT_EQ(met.size(), ring.size()) << "vertex " << v << " met a halfedge twice";
    EXPECT_EQ(met, all) << "vertex " << v;
    bool on_boundary = false;
    for (int32_t h : outgoing[v]) on_boundary = on_boundary || m.boundary(h) || m.boundary(HalfedgeMesh::prev(h));
    EXPECT_EQ(m.boundary(ring.back()), on_boundary) << "vertex " << v;
  }
}

int euler(const HalfedgeMesh& m) {
  std::set<uint32_t> used;
  for (const auto& f : m.faces) used.insert(f.begin(), f.end());
  return int(used.size()) - int(m.edge_count()) + int(m.face_count());
}

size_t boundary_halfedges(const HalfedgeMesh& m) {
  size_t n = 0;
  for (int32_t h = 0; h < int32_t(m.halfedge_count()); ++h) n += m.boundary(h);
  return n;
}

TEST(HalfedgeMesh, CubeIsClosedWithTwelveFacesEighteenEdges) {
  const HalfedgeMesh m = build_halfedge_mesh(make_cube_surface(glm::dvec3(0.0), 1.0, 1));
  expect_invariants(m);
  expect_vertex_fans(m);
  EXPECT_EQ(m.face_count(), 12u);
  EXPECT_EQ(m.edge_count(), 18u);
  EXPECT_EQ(m.vertex_count(), 8u);
  EXPECT_EQ(boundary_halfedges(m), 0u);
  EXPECT_EQ(euler(m), 2);
  EXPECT_TRUE(m.split_edges.empty());
  EXPECT_EQ(m.dropped_triangles, 0u);
  // Wound outwards: the enclosed volume is +8 (side 2).
  double volume = 0.0;
  for (const auto& f : m.faces)
    volume += glm::dot(m.positions[f[0]], glm::cross(m.positions[f[1]], m.positions[f[2]])) / 6.0;
  EXPECT_NEAR(volume, 8.0, 1e-12);
}

TEST(HalfedgeMesh, SubdividedCubeAndIcospheresAreClosedSpheres) {
  for (uint32_t n : {2u, 5u}) {
    const HalfedgeMesh m = build_halfedge_mesh(make_cube_surface(glm::dvec3(1.0, 2.0, 3.0), 0.5, n));
    expect_invariants(m);
    expect_vertex_fans(m);
    EXPECT_EQ(m.face_count(), 12u * n * n);
    EXPECT_EQ(boundary_halfedges(m), 0u);
    EXPECT_EQ(euler(m), 2);
  }
  for (uint32_t s = 0; s <= 3; ++s) {
    const HalfedgeMesh m = build_halfedge_mesh(make_icosphere(glm::dvec3(0.0), 1.0, s));
    expect_invariants(m);
    expect_vertex_fans(m);
    const uint32_t p = 1u << (2 * s);  // 4^s
    EXPECT_EQ(m.face_count(), 20u * p);
    EXPECT_EQ(m.edge_count(), 30u * p);
    EXPECT_EQ(m.vertex_count(), 10u * p + 2u);
    EXPECT_EQ(boundary_halfedges(m), 0u);
    EXPECT_TRUE(m.split_edges.empty()) << "icosphere " << s << " is consistently oriented";
    EXPECT_EQ(euler(m), 2);
  }
}

TEST(HalfedgeMesh, OpenDiskHasOneBoundaryLoop) {
  const SurfaceMesh disk = test::make_disk(4);
  const HalfedgeMesh m = build_halfedge_mesh(disk);
  expect_invariants(m);
  expect_vertex_fans(m);
  EXPECT_EQ(euler(m), 1);
  EXPECT_EQ(m.face_count(), 6u * 4u * 4u);
  EXPECT_EQ(boundary_halfedges(m), 24u);  // the outer ring's 6 * 4 segments
  // Following the boundary from one boundary halfedge visits all of them once and comes back.
  int32_t start = -1;
  for (int32_t h = 0; h < int32_t(m.halfedge_count()); ++h)
    if (m.boundary(h)) start = h;
  ASSERT_GE(start, 0);
  size_t steps = 0;
  int32_t h = start;
  do {
    int32_t g = HalfedgeMesh::next(h);  // leaves target(h); turn until the boundary
    while (!m.boundary(g)) g = m.next_around(g);
    EXPECT_EQ(m.vertex(g), m.target(h));
    EXPECT_DOUBLE_EQ(glm::length(m.positions[m.vertex(g)]), 1.0);
    h = g;
    ++steps;
  } while (h != start && steps <= m.halfedge_count());
  EXPECT_EQ(steps, 24u);
}

SurfaceMesh fan_of_three() {
  // Three triangles on edge (0, 1): a "book" of three pages.
  SurfaceMesh m;
  m.name = "book.off";
  m.points = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return m;
}

TEST(HalfedgeMesh, NonManifoldEdgeIsRejectedNamingMeshAndEdge) {
  try {
    build_halfedge_mesh(fan_of_three(), NonManifold::Reject);
    FAIL() << "a non-manifold edge was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.source(), "book.off");
    EXPECT_NE(what.find("edge (0, 1)"), std::string::npos) << what;
    EXPECT_NE(what.find("3 triangles (0, 1, 2)"), std::string::npos) << what;
    EXPECT_NE(what.find("not a 2-manifold"), std::string::npos) << what;
  }
}

TEST(HalfedgeMesh, NonManifoldEdgeIsSplitIntoBoundaries) {
  const HalfedgeMesh m = build_halfedge_mesh(fan_of_three());
  expect_invariants(m);
  ASSERT_EQ(m.split_edges.size(), 1u);
  EXPECT_EQ(m.split_edges[0], (std::array<uint32_t, 2>{0, 1}));
  EXPECT_EQ(boundary_halfedges(m), 9u);  // nothing shared: 3 triangles, 9 edges
  EXPECT_EQ(m.edge_count(), 9u);
  std::set<uint32_t> on_01;
  for (int32_t h = 0; h < 9; ++h)
    if (std::min(m.vertex(h), m.target(h)) == 0 && std::max(m.vertex(h), m.target(h)) == 1) on_01.insert(m.edge_of[h]);
  EXPECT_EQ(on_01.size(), 3u);  // three separate edges along (0, 1)
}

TEST(HalfedgeMesh, InconsistentOrientationIsRejectedOrSplit) {
  SurfaceMesh m;
  m.name = "flipped.obj";
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
  m.triangles = {{0, 1, 2}, {0, 1, 3}};  // both run 0 -> 1
  try {
    build_halfedge_mesh(m, NonManifold::Reject);
    FAIL() << "inconsistent orientation was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.source(), "flipped.obj");
    EXPECT_NE(what.find("triangles 0 and 1 both run from point 0 to point 1"), std::string::npos) << what;
    EXPECT_NE(what.find("orientations disagree"), std::string::npos) << what;
  }
  const HalfedgeMesh split = build_halfedge_mesh(m);
  expect_invariants(split);
  EXPECT_EQ(split.split_edges.size(), 1u);
  EXPECT_EQ(boundary_halfedges(split), 6u);
  // Flipping the second triangle makes it a manifold strip with one shared edge.
  m.triangles[1] = {1, 0, 3};
  const HalfedgeMesh fixed = build_halfedge_mesh(m, NonManifold::Reject);
  expect_invariants(fixed);
  expect_vertex_fans(fixed);
  EXPECT_EQ(boundary_halfedges(fixed), 4u);
}

TEST(HalfedgeMesh, RepeatedPointTrianglesAreDroppedZeroAreaOnesKept) {
  // A T-junction closed by a zero-area sliver: point 3 lies on segment (0, 1); the two upper
  // triangles run 0 -> 3 -> 1, the lower one 1 -> 0, and the sliver (1, 3, 0) joins them.
  SurfaceMesh m;
  m.name = "slivers.stl";
  m.points = {{0, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, 0, 0}, {1, -1, 0}};
  m.triangles = {{0, 3, 2}, {2, 2, 0}, {3, 1, 2}, {1, 3, 0}, {0, 4, 1}};
  const HalfedgeMesh h = build_halfedge_mesh(m, NonManifold::Reject);
  expect_invariants(h);
  expect_vertex_fans(h);
  EXPECT_EQ(h.dropped_triangles, 1u);
  EXPECT_EQ(h.face_count(), 4u);
  EXPECT_EQ(h.face_of_triangle[1], -1);
  EXPECT_EQ(h.face_of_triangle[3], 2);  // the sliver is kept
  EXPECT_EQ(h.triangle_of_face[3], 4u);
  EXPECT_EQ(boundary_halfedges(h), 4u);
  EXPECT_EQ(euler(h), 1);
  // The sliver's three sides are all shared: it is what keeps the surface in one piece.
  for (int32_t k = 0; k < 3; ++k) EXPECT_FALSE(h.boundary(3 * 2 + k));
}

TEST(HalfedgeMesh, BadIndicesAndPointsAreInputErrors) {
  SurfaceMesh m;
  m.name = "bad.ply";
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 7}};
  try {
    build_halfedge_mesh(m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "bad.ply: triangle 1 refers to point 7, but there are only 3 points");
  }
  m.triangles = {{0, 1, 2}};
  m.points[2].y = std::numeric_limits<double>::quiet_NaN();
  try {
    build_halfedge_mesh(m);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "bad.ply: point 2 is not finite");
  }
}

TEST(HalfedgeMesh, BowtieVertexIsKeptWithOneFanNamed) {
  SurfaceMesh m;
  m.name = "bowtie";
  m.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  m.triangles = {{0, 1, 2}, {0, 3, 4}};  // two triangles touching at point 0 only
  const HalfedgeMesh h = build_halfedge_mesh(m, NonManifold::Reject);
  expect_invariants(h);
  EXPECT_EQ(h.edge_count(), 6u);
  EXPECT_EQ(boundary_halfedges(h), 6u);
  EXPECT_EQ(fan(h, 0).size(), 1u);  // one of the two fans
  EXPECT_EQ(h.vertex(h.vertex_halfedge[0]), 0u);
}

}  // namespace
}  // namespace prismoid
