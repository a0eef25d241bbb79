#include "renderer/volume/region_mesh.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

#include <glm/common.hpp>

#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {

namespace {

using Key = std::tuple<int, int, int>;

int floor_div(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// Per axis: the lattice step (gcd of every size and of every corner's offset from the first
// box's corner) and the lattice's offset in [0, step).
struct Lattice {
  glm::ivec3 step{0}, offset{0};
};

Lattice lattice_of(const std::vector<IndexBox>& regions) {
  Lattice l;
  for (const IndexBox& b : regions)
    for (int a = 0; a < 3; ++a) l.step[a] = std::gcd(std::gcd(l.step[a], b.size[a]), b.min[a] - regions.front().min[a]);
  for (int a = 0; a < 3; ++a) l.offset[a] = regions.front().min[a] - floor_div(regions.front().min[a], l.step[a]) * l.step[a];
  return l;
}

}  // namespace

TetMesh make_region_mesh(const SampledGrid& grid, const std::vector<IndexBox>& regions, double density_scale) {
  validate(grid);
  for (const IndexBox& b : regions)
    if (b.size.x <= 0 || b.size.y <= 0 || b.size.z <= 0) throw InputError(grid.name, "a region box has no samples");
  TetMesh mesh;
  mesh.name = grid.name + " (regions)";
  if (regions.empty()) return mesh;
  const Lattice l = lattice_of(regions);
  std::set<Key> blocks;  // lattice blocks of the union, each once
  for (const IndexBox& b : regions) {
    glm::ivec3 first, last;
    for (int a = 0; a < 3; ++a) {
      first[a] = floor_div(b.min[a] - l.offset[a], l.step[a]);
      last[a] = floor_div(b.min[a] + b.size[a] - l.offset[a], l.step[a]);  // exclusive: sizes are multiples of the step
    }
    for (int k = first.z; k < last.z; ++k)
      for (int j = first.y; j < last.y; ++j)
        for (int i = first.x; i < last.x; ++i) blocks.insert({i, j, k});
  }
  const glm::ivec3 top = glm::ivec3(grid.dims) - 1;  // the last sample per axis
  std::map<Key, uint32_t> point_of;
  auto point = [&](const glm::ivec3& s) {
    const auto [it, added] = point_of.try_emplace({s.x, s.y, s.z}, uint32_t(mesh.points.size()));
    if (added) mesh.points.push_back(grid.position(glm::dvec3(s)));
    return it->second;
  };
  // Kuhn split: the six paths from corner 000 to corner 111 along the cube's edges.
  static const int kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& [i, j, k] : blocks) {
    const glm::ivec3 block(i, j, k);
    const glm::ivec3 lo = glm::clamp(l.offset + block * l.step, glm::ivec3(0), top);
    const glm::ivec3 hi = glm::clamp(l.offset + (block + 1) * l.step, glm::ivec3(0), top);
    if (hi.x <= lo.x || hi.y <= lo.y || hi.z <= lo.z) continue;  // outside the samples' box, or flat there
    for (const auto& path : kPaths) {
      glm::ivec3 corner = lo;
      std::array<uint32_t, 4> tet{point(corner), 0, 0, 0};
      for (int s = 0; s < 3; ++s) {
        corner[path[s]] = hi[path[s]];
        tet[s + 1] = point(corner);
      }
      const auto& p = mesh.points;
      if (signed_volume(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]) < 0.0) std::swap(tet[2], tet[3]);
      mesh.tets.push_back(tet);
    }
  }
  for (const glm::dvec3& p : mesh.points) {
    const double v = evaluate(grid, p);
    mesh.point_scalars.push_back(v);
    mesh.point_extinction.push_back(std::max(density_scale * v, 0.0));
  }
  for (const auto& t : mesh.tets) {
    const glm::dvec3 centroid = 0.25 * (mesh.points[t[0]] + mesh.points[t[1]] + mesh.points[t[2]] + mesh.points[t[3]]);
    mesh.cell_extinction.push_back(std::max(density_scale * evaluate(grid, centroid), 0.0));
  }
  mesh.name = grid.name + " (" + std::to_string(mesh.tets.size()) + " tetrahedra bounding " + std::to_string(blocks.size()) +
              " blocks of a sampled grid)";
  return mesh;
}

std::vector<IndexBox> whole_grid(const SampledGrid& grid) { return {{glm::ivec3(0), glm::ivec3(grid.dims)}}; }

std::vector<IndexBox> blocks_above(const SampledGrid& grid, double threshold, int block) {
  validate(grid);
  if (block <= 0) throw InputError(grid.name, "blocks need at least one sample per axis");
  std::vector<IndexBox> boxes;
  const glm::ivec3 top = glm::ivec3(grid.dims) - 1;
  for (int k = 0; k < top.z; k += block)
    for (int j = 0; j < top.y; j += block)
      for (int i = 0; i < top.x; i += block) {
        bool above = false;
        for (int z = k; z <= std::min(k + block, top.z) && !above; ++z)
          for (int y = j; y <= std::min(j + block, top.y) && !above; ++y)
            for (int x = i; x <= std::min(i + block, top.x) && !above; ++x)
              above = double(grid.values[grid.index(uint32_t(x), uint32_t(y), uint32_t(z))]) > threshold;
        if (above) boxes.push_back({{i, j, k}, glm::ivec3(block)});
      }
  return boxes;
}

}  // namespace prismoid::volume
