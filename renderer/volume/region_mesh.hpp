#pragma once
// Proxy geometry for marching a sampled grid: the union of index-space boxes (OpenVDB's active
// leaf nodes, blocks where the field is above a threshold, or the whole grid) bounded by
// tetrahedra, which interval-march draws and marches the grid inside.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/volume/sampled_grid.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::volume {

// Samples min .. min + size - 1 per axis (a box of `size` samples, as an OpenVDB leaf of 8^3
// voxels is), in the grid's index space. The region it bounds reaches to sample min + size,
// the next box's first sample, so that boxes side by side leave no gap (clipped to the grid).
struct IndexBox {
  glm::ivec3 min{0};
  glm::ivec3 size{0};
};

// The union of the boxes as conforming tetrahedra. The boxes' corners are taken on one lattice
// (per axis the greatest common divisor of their sizes and corner offsets: 8 for VDB leaves),
// each lattice block of the union is one cube of 6 Kuhn tetrahedra (the diagonal from its
// lower to its upper corner, so every face shared by two blocks is split along the same
// diagonal), clipped to the samples' box; blocks nothing of which lies inside are dropped.
// Point scalars are the grid at the points, point extinction density_scale times its positive
// part, cell extinction at the centroid (the linear interpolant the non-marching modes show).
TetMesh make_region_mesh(const SampledGrid& grid, const std::vector<IndexBox>& regions, double density_scale = 1.0);

// The whole grid as one box.
std::vector<IndexBox> whole_grid(const SampledGrid& grid);
// The blocks of block^3 samples (from sample 0) whose trilinear field exceeds `threshold`
// somewhere: one of their samples, the next block's first ones included, does.
std::vector<IndexBox> blocks_above(const SampledGrid& grid, double threshold, int block = 8);

}  // namespace prismoid::volume
