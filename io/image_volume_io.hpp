#pragma once
// Image volumes (voxel grids) as tetrahedral meshes: .vti (VTK XML image data), .mhd/.mha
// (MetaImage) through VTK's readers, and INRIMAGE-4 .inr / .inr.gz (CGAL's demo data) through
// a small strict parser of our own. Each voxel becomes a mesh point carrying the voxel's value;
// each cell between eight neighbouring voxel centres is cut into six tetrahedra the same way
// (the Kuhn split), so neighbouring cells share their faces exactly and the mesh is conforming.
#include <cstdint>
#include <string>

#include "io/progress.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::io {

// The interactive guard on voxel data (images and OpenVDB grids) the CLI and the window apply:
// 50 million tetrahedra, about 1.2 GB of GPU buffers; larger needs --subsample.
constexpr uint64_t kInteractiveMaxCells = 50'000'000;

struct ImageReadOptions {
  // The point array to use (vectors by magnitude); empty: the file's active scalars, or its only
  // array. INRIMAGE files hold one unnamed array, so it must stay empty for them.
  std::string array;
  ArrayRole role = ArrayRole::Extinction;
  double density_scale = 1.0;  // multiplies the voxel values (Extinction role only)
  // Keep every subsample-th voxel along each axis (1 keeps all); the spacing grows to match.
  uint32_t subsample = 1;
  // The dataset-size guard: more tetrahedra than this is refused before the voxels are read.
  uint64_t max_cells = 200'000'000;
  Progress progress;  // called per slice while converting; returning false cancels (Cancelled)
};

// Whether `path` has an extension read_image_volume understands (.vti, .mhd, .mha, .inr, .inr.gz).
bool is_image_volume_path(const std::string& path);

// Point scalars are the voxel values; for the Extinction role point_extinction is value *
// density_scale (cell_extinction the mean of each tetrahedron's four points), for the Scalars
// role cell_extinction is density_scale. Point (i, j, k) sits at origin + (i, j, k) * spacing.
// Throws InputError naming the file and the problem: missing or unreadable file, a header it does
// not understand, truncated voxel data, an image thinner than two voxels along an axis, an unknown
// array, or more tetrahedra than max_cells (the message names the smallest subsample that fits).
TetMesh read_image_volume(const std::string& path, const ImageReadOptions& options = {});

// 6 (nx-1)(ny-1)(nz-1) for an image of nx x ny x nz voxels after keeping every subsample-th
// (saturating at the largest uint64_t). Each of dims must be at least 1.
uint64_t image_tet_count(const uint64_t dims[3], uint32_t subsample);

}  // namespace prismoid::io
