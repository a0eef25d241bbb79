#include "renderer/surface/fastatlas/scene_adjacency.hpp"

#include <map>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "renderer/surface/fastatlas/atlas_filter.hpp"

namespace prismoid::fastatlas {

namespace {

glm::dvec3 unit_normal(const HalfedgeMesh& m, uint32_t f) {
  const auto& t = m.faces[f];
  const glm::dvec3 n = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
  const double l = glm::length(n);
  return l > 0.0 ? n / l : glm::dvec3(0.0);
}

}  // namespace

SceneAdjacency scene_adjacency(const SurfaceScene& scene, double max_degrees) {
  std::vector<glm::dvec3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  for (const SceneMesh& mesh : scene.meshes) {
    // Welded: each position's first vertex of this mesh stands for all of them.
    std::map<std::array<double, 3>, uint32_t> first;
    std::vector<uint32_t> welded(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const glm::dvec3& p = mesh.positions[v];
      const auto [it, fresh] = first.try_emplace({p.x, p.y, p.z}, uint32_t(positions.size()));
      if (fresh) positions.push_back(p);
      welded[v] = it->second;
    }
    for (const auto& t : mesh.triangles) {
      for (uint32_t k : t)
        if (k >= welded.size()) throw std::invalid_argument("scene_adjacency: mesh " + mesh.name + " names a vertex it does not have");
      triangles.push_back({welded[t[0]], welded[t[1]], welded[t[2]]});
    }
  }
  SceneAdjacency a;
  a.mesh = build_halfedge_mesh("the scene", positions, triangles, NonManifold::Split);
  const size_t n = triangles.size();
  a.vertices = triangles;
  a.neighbours.assign(n, {kNoTriangle, kNoTriangle, kNoTriangle});
  a.smooth.assign(n, 0);
  const HalfedgeMesh& m = a.mesh;
  for (uint32_t f = 0; f < m.face_count(); ++f) {
    const uint32_t t = m.triangle_of_face[f];
    const glm::dvec3 own = unit_normal(m, f);
    for (uint32_t k = 0; k < 3; ++k) {
      const int32_t twin = m.twin[3 * f + k];
      if (twin == kNoHalfedge) continue;
      const uint32_t g = uint32_t(HalfedgeMesh::face(twin));
      a.neighbours[t][k] = m.triangle_of_face[g];
      if (tap_usable(false, true, own, unit_normal(m, g), max_degrees)) a.smooth[t] |= uint8_t(1u << k);
    }
  }
  return a;
}

std::vector<uint8_t> face_visibility(const SceneAdjacency& adjacency, const std::vector<uint8_t>& triangle_visible) {
  const HalfedgeMesh& m = adjacency.mesh;
  if (triangle_visible.size() != m.face_of_triangle.size())
    throw std::invalid_argument("face_visibility: one flag per triangle of the scene");
  std::vector<uint8_t> faces(m.face_count(), 0);
  for (uint32_t f = 0; f < m.face_count(); ++f) faces[f] = triangle_visible[m.triangle_of_face[f]];
  return faces;
}

}  // namespace prismoid::fastatlas
