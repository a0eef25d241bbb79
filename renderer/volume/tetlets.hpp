#pragma once
// Tetlets (the interval-shading paper's future work): cells grouped so that one mesh-shader
// workgroup draws up to `max_cells` of them and loads each of their points once into shared
// memory, instead of once per cell corner. Plain data, no Vulkan.
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::volume {

struct Tetlets {
  uint32_t max_cells = 0;
  uint32_t max_points = 0;
  std::vector<glm::uvec4> headers;  // per tetlet: first entry of `points`, point count, first entry of `cells`, cell count
  std::vector<uint32_t> points;     // each tetlet's distinct points, global indices
  std::vector<glm::uvec2> cells;    // global cell index, and its 4 corners as 8-bit indices into the tetlet's points
  double points_per_cell() const { return cells.empty() ? 0.0 : double(points.size()) / double(cells.size()); }
};

// Groups every cell into exactly one tetlet: cells are visited in Morton order of their
// centroids (neighbours in space are neighbours in the list) and added to the current tetlet
// while it has fewer than max_cells cells and the new cell's points keep it within max_points
// (at most 255, the 8-bit corner indices). Deterministic.
Tetlets build_tetlets(const TetMesh& mesh, uint32_t max_cells, uint32_t max_points);

}  // namespace prismoid::volume
