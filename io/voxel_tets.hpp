#pragma once
// Voxel grids as conforming tetrahedral meshes (the Kuhn split), and the dataset-size guard that
// runs on an image's header before its voxels are read. Plain C++ (no VTK), shared by every
// image reader and linked by the fuzz targets. Internal to io/.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "io/image_volume_io.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::io::detail {

// A voxel grid after subsampling: value (i, j, k) at index i + nx (j + ny k), at origin + (i, j, k) * spacing.
struct VoxelGrid {
  uint64_t dims[3] = {0, 0, 0};
  glm::dvec3 origin{0.0};
  glm::dvec3 spacing{1.0};
  std::vector<double> values;
};

// Voxels kept along an axis of n voxels when keeping every subsample-th.
inline uint64_t kept_voxels(uint64_t n, uint32_t subsample) { return (n - 1) / subsample + 1; }

// Throws InputError(path, ...) when an image of `dims` voxels (before subsampling) cannot become a
// mesh under `options`: a zero subsample, fewer than two kept voxels along an axis, more
// tetrahedra than options.max_cells (naming the smallest subsample that fits), or more points
// than 32-bit indices address.
void check_image_size(const std::string& path, const uint64_t dims[3], const ImageReadOptions& options);

// The grid's voxels as mesh points and each cell of eight as six positively oriented
// tetrahedra, all cells split alike so that neighbours share faces. Point scalars, extinction and
// progress as read_image_volume documents. The grid must have passed check_image_size and hold
// dims[0] * dims[1] * dims[2] values.
TetMesh voxel_grid_to_tets(const VoxelGrid& grid, const std::string& name, const ImageReadOptions& options);

// The mesh's extinction from its point values (density times density_scale, linear in each
// cell), with each cell's mean as its cell extinction (for statistics; rendering interpolates
// the points). The one place voxel data becomes extinction (images and OpenVDB grids).
void set_point_extinction(TetMesh& mesh, const std::vector<double>& values, double density_scale);

}  // namespace prismoid::io::detail
