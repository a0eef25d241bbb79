#include "app/viewer/scene_merge.hpp"
#include "scene/tet_mesh.hpp"

#include <algorithm>

namespace prismoid::app {

namespace {

bool has_scalars(const TetMesh* m) { return !m->point_scalars.empty() || !m->cell_scalars.empty(); }

// What the union stores per point; a mesh that stores it per cell gives each cell its own points.
struct PointFields {
  bool extinction = false;
  bool scalars = false;
};

void append(TetMesh& out, const TetMesh& m, PointFields per_point, bool scalars) {
  const bool own_points = (per_point.extinction && !m.linear_extinction()) || (per_point.scalars && m.point_scalars.empty());
  const auto base = uint32_t(out.points.size());
  out.cell_extinction.insert(out.cell_extinction.end(), m.cell_extinction.begin(), m.cell_extinction.end());
  if (scalars && !per_point.scalars) out.cell_scalars.insert(out.cell_scalars.end(), m.cell_scalars.begin(), m.cell_scalars.end());
  if (!own_points) {
    out.points.insert(out.points.end(), m.points.begin(), m.points.end());
    for (const auto& t : m.tets) out.tets.push_back({t[0] + base, t[1] + base, t[2] + base, t[3] + base});
    if (per_point.extinction) out.point_extinction.insert(out.point_extinction.end(), m.point_extinction.begin(), m.point_extinction.end());
    if (per_point.scalars) out.point_scalars.insert(out.point_scalars.end(), m.point_scalars.begin(), m.point_scalars.end());
    return;
  }
  for (size_t c = 0; c < m.tets.size(); ++c) {
    const uint32_t first = uint32_t(out.points.size());
    for (const uint32_t v : m.tets[c]) {
      out.points.push_back(m.points[v]);
      if (per_point.extinction) out.point_extinction.push_back(m.linear_extinction() ? m.point_extinction[v] : m.cell_extinction[c]);
      if (per_point.scalars) out.point_scalars.push_back(m.point_scalars.empty() ? m.cell_scalars[c] : m.point_scalars[v]);
    }
    out.tets.push_back({first, first + 1, first + 2, first + 3});
  }
}

}  // namespace

TetMesh merge_meshes(const std::vector<const TetMesh*>& meshes) {
  TetMesh out;
  const bool scalars = !meshes.empty() && std::all_of(meshes.begin(), meshes.end(), has_scalars);
  PointFields per_point;
  per_point.extinction = std::any_of(meshes.begin(), meshes.end(), [](const TetMesh* m) { return m->linear_extinction(); });
  per_point.scalars = scalars && std::any_of(meshes.begin(), meshes.end(), [](const TetMesh* m) { return !m->point_scalars.empty(); });
  for (const TetMesh* m : meshes) {
    out.name += (m == meshes.front() ? "" : " + ") + m->name;
    append(out, *m, per_point, scalars);
  }
  return out;
}

}  // namespace prismoid::app
