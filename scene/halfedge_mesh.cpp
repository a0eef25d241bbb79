#include "scene/halfedge_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "scene/input_error.hpp"

namespace prismoid {

namespace {

std::string edge_text(uint32_t a, uint32_t b) { return "(" + std::to_string(a) + ", " + std::to_string(b) + ")"; }

}  // namespace

HalfedgeMesh build_halfedge_mesh(const std::string& name, const std::vector<glm::dvec3>& positions,
                                 const std::vector<std::array<uint32_t, 3>>& triangles, NonManifold policy) {
  HalfedgeMesh mesh;
  mesh.name = name;
  mesh.positions = positions;
  for (size_t i = 0; i < positions.size(); ++i) {
    const auto& p = positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(name, "point " + std::to_string(i) + " is not finite");
  }
  mesh.face_of_triangle.assign(triangles.size(), -1);
  for (size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    for (uint32_t v : tri)
      if (v >= positions.size())
        throw InputError(name, "triangle " + std::to_string(t) + " refers to point " + std::to_string(v) + ", but there are only " +
                                   std::to_string(positions.size()) + " points");
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) {
      ++mesh.dropped_triangles;
      continue;
    }
    mesh.face_of_triangle[t] = static_cast<int32_t>(mesh.faces.size());
    mesh.triangle_of_face.push_back(static_cast<uint32_t>(t));
    mesh.faces.push_back(tri);
  }

  const auto halfedges = static_cast<int32_t>(3 * mesh.faces.size());
  mesh.twin.assign(halfedges, kNoHalfedge);
  mesh.edge_of.assign(halfedges, 0);

  // Halfedges sorted by their undirected edge (smaller point first): each run is one edge.
  std::vector<std::tuple<uint32_t, uint32_t, int32_t>> keyed(halfedges);
  for (int32_t h = 0; h < halfedges; ++h) {
    const uint32_t a = mesh.vertex(h), b = mesh.target(h);
    keyed[h] = {std::min(a, b), std::max(a, b), h};
  }
  std::sort(keyed.begin(), keyed.end());
  for (size_t i = 0; i < keyed.size();) {
    size_t j = i + 1;
    while (j < keyed.size() && std::get<0>(keyed[j]) == std::get<0>(keyed[i]) && std::get<1>(keyed[j]) == std::get<1>(keyed[i])) ++j;
    const uint32_t lo = std::get<0>(keyed[i]), hi = std::get<1>(keyed[i]);
    if (j - i == 2) {
      const int32_t h0 = std::get<2>(keyed[i]), h1 = std::get<2>(keyed[i + 1]);
      if (mesh.vertex(h0) != mesh.vertex(h1)) {
        mesh.twin[h0] = h1;
        mesh.twin[h1] = h0;
        i = j;
        continue;
      }
      if (policy == NonManifold::Reject)
        throw InputError(name, "triangles " + std::to_string(mesh.triangle_of_face[h0 / 3]) + " and " +
                                   std::to_string(mesh.triangle_of_face[h1 / 3]) + " both run from point " +
                                   std::to_string(mesh.vertex(h0)) + " to point " + std::to_string(mesh.target(h0)) +
                                   " along edge " + edge_text(lo, hi) + ": their orientations disagree (one is flipped)");
    } else if (j - i > 2 && policy == NonManifold::Reject) {
      std::string list;
      for (size_t k = i; k < j; ++k) list += (k == i ? "" : ", ") + std::to_string(mesh.triangle_of_face[std::get<2>(keyed[k]) / 3]);
      throw InputError(name, "edge " + edge_text(lo, hi) + " is shared by " + std::to_string(j - i) +
                                 " triangles (" + list + "): the surface is not a 2-manifold there");
    }
    if (j - i >= 2) mesh.split_edges.push_back({lo, hi});  // every halfedge here stays a boundary
    i = j;
  }

  // Edge ids in the order halfedges first meet them.
  std::vector<bool> named(halfedges, false);
  for (int32_t h = 0; h < halfedges; ++h) {
    if (named[h]) continue;
    const auto e = static_cast<uint32_t>(mesh.edge_halfedge.size());
    const int32_t t = mesh.twin[h];
    mesh.edge_of[h] = e;
    named[h] = true;
    if (t != kNoHalfedge) {
      mesh.edge_of[t] = e;
      named[t] = true;
    }
    mesh.edge_halfedge.push_back(std::max(h, t));
  }

  // An outgoing halfedge per vertex, the first of its fan where the vertex is on a boundary.
  mesh.vertex_halfedge.assign(positions.size(), kNoHalfedge);
  for (int32_t h = 0; h < halfedges; ++h) {
    int32_t& slot = mesh.vertex_halfedge[mesh.vertex(h)];
    if (slot == kNoHalfedge || mesh.twin[HalfedgeMesh::prev(h)] == kNoHalfedge) {
      if (slot == kNoHalfedge || mesh.twin[HalfedgeMesh::prev(slot)] != kNoHalfedge) slot = h;
    }
  }
  return mesh;
}

HalfedgeMesh build_halfedge_mesh(const SurfaceMesh& mesh, NonManifold policy) {
  return build_halfedge_mesh(mesh.name, mesh.points, mesh.triangles, policy);
}

HalfedgeMesh build_halfedge_mesh(const SceneMesh& mesh, NonManifold policy) {
  return build_halfedge_mesh(mesh.name, mesh.positions, mesh.triangles, policy);
}

glm::dvec3 face_center(const HalfedgeMesh& mesh, uint32_t f) {
  const auto& t = mesh.faces[f];
  return (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
}

}  // namespace prismoid
