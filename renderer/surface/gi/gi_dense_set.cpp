#include "renderer/surface/gi/gi_dense_set.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "renderer/surface/htex/htex_layout.hpp"
#include "renderer/surface/htex/htex_walk.hpp"
#include "scene/halfedge_mesh.hpp"

namespace prismoid::surface {

GiDenseSet build_gi_dense_set(const SurfaceScene& scene, const GiDenseSetOptions& options) {
  validate(scene);
  std::vector<HalfedgeMesh> meshes;
  meshes.reserve(scene.meshes.size());
  for (const SceneMesh& m : scene.meshes) meshes.push_back(build_halfedge_mesh(m));
  const htex::AtlasLayout layout(meshes, {.texels_per_unit = options.texels_per_unit});

  GiDenseSet set;
  set.max_radius = options.max_radius;
  for (int32_t r = 1; r <= static_cast<int32_t>(options.max_radius); ++r)
    for (int32_t di = -r; di <= r; ++di)
      for (int32_t dj = -r; dj <= r; ++dj)
        if (std::max(std::abs(di), std::abs(dj)) == r) set.offsets.push_back({di, dj});
  set.table_width = static_cast<uint32_t>(set.offsets.size());

  // Per mesh and texel (edge, i, j): the sample index, or kNoNeighbour.
  std::vector<std::vector<uint32_t>> index(meshes.size());
  std::vector<uint32_t> side(meshes.size(), 0);
  uint32_t first_triangle = 0;
  for (uint32_t m = 0; m < meshes.size(); ++m) {
    const HalfedgeMesh& mesh = meshes[m];
    const SceneMesh& scene_mesh = scene.meshes[m];
    const htex::MeshLayout& ml = layout.meshes()[m];
    const uint32_t n = ml.side(std::min(options.level, ml.levels - 1));
    side[m] = n;
    index[m].assign(size_t(mesh.edge_count()) * n * n, kNoNeighbour);
    for (uint32_t e = 0; e < mesh.edge_count(); ++e)
      for (uint32_t j = 0; j < n; ++j)
        for (uint32_t i = 0; i < n; ++i) {
          const htex::TexelPoint tp = htex::texel_point(mesh, e, n, i, j);
          if (tp.ghost) continue;
          const uint32_t triangle = mesh.triangle_of_face[tp.face];
          const auto& corners = scene_mesh.triangles[triangle];
          const glm::dvec3 normal = glm::cross(scene_mesh.positions[corners[1]] - scene_mesh.positions[corners[0]],
                                               scene_mesh.positions[corners[2]] - scene_mesh.positions[corners[0]]);
          const double len = glm::length(normal);
          if (!(len > 0.0) || !std::isfinite(len)) continue;  // zero-area triangle: nothing to shade
          GiDenseSample s;
          s.mesh = m;
          s.triangle = triangle;
          s.global_triangle = first_triangle + triangle;
          s.bary = tp.bary;
          s.position = tp.position;
          s.viewer = normal / len;
          s.edge = e;
          s.i = i;
          s.j = j;
          s.side = n;
          index[m][(size_t(e) * n + j) * n + i] = static_cast<uint32_t>(set.samples.size());
          set.samples.push_back(s);
        }
    first_triangle += static_cast<uint32_t>(scene_mesh.triangles.size());
  }

  set.neighbours.assign(set.samples.size() * set.table_width, kNoNeighbour);
  for (uint32_t k = 0; k < set.samples.size(); ++k) {
    const GiDenseSample& s = set.samples[k];
    const uint32_t n = side[s.mesh];
    for (uint32_t c = 0; c < set.table_width; ++c) {
      const auto t = htex::walk_texel(meshes[s.mesh], n, {s.edge, int32_t(s.i), int32_t(s.j)}, set.offsets[c]);
      if (!t) continue;
      const uint32_t found = index[s.mesh][(size_t(t->edge) * n + uint32_t(t->j)) * n + uint32_t(t->i)];
      if (found != k) set.neighbours[size_t(k) * set.table_width + c] = found;
    }
  }
  return set;
}

}  // namespace prismoid::surface
