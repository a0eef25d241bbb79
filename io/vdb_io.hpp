#pragma once
// OpenVDB .vdb files (sparse voxel grids: fog volumes and level sets) read as tetrahedral meshes
// or as dense samples, described for `prismoid info`, and written from closed surfaces through
// OpenVDB's own tools. OpenVDB's headers are included by io/vdb_io.cpp alone: no OpenVDB type
// appears here.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "io/progress.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/bounds.hpp"
#include "scene/surface_mesh.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::io {

bool is_vdb_path(const std::string& path);

enum class VdbClass { FogVolume, LevelSet, Unknown };
const char* vdb_class_name(VdbClass c);  // "fog volume", "level set", "unknown"

struct VdbGridInfo {
  std::string name;
  std::string value_type;  // OpenVDB's name: "float", "double", "vec3s", ...
  VdbClass grid_class = VdbClass::Unknown;
  glm::dvec3 voxel_size{0.0};
  bool linear_transform = true;  // false for frustum (and other non-affine) transforms
  uint64_t active_voxels = 0;    // active tiles count every voxel they cover
  glm::ivec3 index_min{0}, index_max{0};  // inclusive box of the active voxels (index space)
  Bounds world;                           // the centres of the corners of that box, in world space
  bool has_range = false;                 // scalar grids with active voxels only
  double value_min = 0.0, value_max = 0.0;  // over the active voxels
  uint64_t leaf_nodes = 0;
  uint64_t memory_bytes = 0;  // OpenVDB's own count of the tree in memory
  // What read_vdb_voxels makes of it (float grids, no subsampling): dual cells and their points.
  uint64_t dual_cells = 0, mesh_points = 0;
  uint64_t tets() const { return 6 * dual_cells; }
};

struct VdbInfo {
  std::string path;
  uint64_t file_bytes = 0;
  std::vector<VdbGridInfo> grids;
};

// Every grid of the file, in the file's order. InputError naming the file when it is missing, not a VDB file,
// truncated or corrupt.
VdbInfo inspect_vdb(const std::string& path);

struct VdbReadOptions {
  std::string grid;  // the float grid's name; empty: the file's first float grid
  ArrayRole role = ArrayRole::Extinction;
  double density_scale = 1.0;
  uint32_t subsample = 1;  // keep 1 voxel in K along each index axis
  uint64_t max_cells = 200'000'000;  // refused beyond, before the mesh is built
  Progress progress;
};

// Voxel tetrahedra, for exact linear interpolation of the grid. Mesh points sit at voxel centres
// (world space through the grid's affine transform). A dual cell (the box between the centres of
// 2x2x2 neighbouring voxels) is kept when any of its 8 corners is active; its inactive corners
// carry the grid's value there (the background, or -background inside a level set): that is what
// the grid means between its active voxels. Each cell is cut by the Kuhn split (io/kuhn_split.hpp)
// as image volumes are, so the mesh is conforming. With subsample K the points are the voxels whose
// index is a multiple of K, and a coarse cell is kept when it holds any active voxel.
//
// Point scalars: the grid's values. Extinction (Extinction role), times density_scale:
// - fog volume (and unknown class): the value itself (density, 0..1 by convention);
// - level set (signed distance, negative inside): OpenVDB's sdfToFogVolume mapping: 0 where the
//   distance is >= 0, -distance / w inside, where w is the depth of the inside band (the smallest
//   distance stored, at most the background), and 1 in the interior beyond the band; cells are kept
//   around the voxels that mapping makes active, so the solid interior is filled.
// The Scalars role puts density_scale in every cell (as the image volumes do).
//
// InputError naming the file: not a VDB file, truncated or corrupt, no float grid or no grid of
// that name (listing the grids), a non-affine transform, no active voxels, a non-finite value,
// more tetrahedra than max_cells (naming a subsample that fits).
TetMesh read_vdb_voxels(const std::string& path, const VdbReadOptions& options = {});

// A float grid sampled densely over the box of its active voxels, for marching through it.
struct VdbBox {
  glm::ivec3 min{0};   // relative to the dense origin (voxel (0,0,0) of `values`)
  glm::ivec3 size{8};  // 8 for leaf nodes; active tiles are larger
};
struct VdbDense {
  glm::uvec3 dims{0};
  glm::dvec3 origin{0.0};   // world position of voxel (0,0,0)'s centre
  glm::dvec3 spacing{0.0};  // world distance between neighbouring voxel centres, per axis
  std::vector<float> values;  // x fastest: values[x + dims.x (y + dims.y z)]; inactive voxels hold the grid's value there (background)
  std::vector<VdbBox> active_boxes;  // leaf nodes holding active voxels, and active tiles
  VdbClass grid_class = VdbClass::Unknown;
  float background = 0.0f;
};
constexpr uint64_t kMaxDenseVoxels = uint64_t(512) << 20;  // 2 GiB of floats

// Uses options.grid and options.subsample (K > 1 keeps voxels whose index is a multiple of K;
// boxes are then in the coarse index space, rounded outward). Throws InputError as
// read_vdb_voxels does, for a transform with rotation or shear (dense samples are axis-aligned),
// and for more than max_voxels voxels.
VdbDense read_vdb_dense(const std::string& path, const VdbReadOptions& options = {}, uint64_t max_voxels = kMaxDenseVoxels);

// Writing: a closed triangle surface as a narrow-band level set (OpenVDB's meshToLevelSet, 3
// voxels each side) or, with fog = true, that level set through sdfToFogVolume (density 1 inside,
// a linear ramp across the inner band, 0 outside). The grid is called "density" (fog) or
// "surface" (level set). voxel_size <= 0: the bounding-box diagonal / 128. Writes `path` itself
// and removes it when the write fails (putting the file in place whole is the caller's,
// app/common/output_files.hpp). InputError for an empty or open surface, a voxel size giving more than
// max_voxels voxels in the padded bounding box or over half the box's smallest side (the grid
// could not hold the inside), no voxel centre inside the surface, or a file that cannot be written.
struct VdbWriteOptions {
  bool fog = true;
  double voxel_size = 0.0;
  uint64_t max_voxels = uint64_t(1) << 30;
  Progress progress;
};
struct VdbWriteReport {
  double voxel_size = 0.0;
  uint64_t active_voxels = 0;
};
VdbWriteReport write_vdb_from_surface(const std::string& path, const SurfaceMesh& surface, const VdbWriteOptions& options);

// A new surface for a closed one: its narrow-band level set at `voxel_size` (<= 0: the bounding
// box's diagonal / 128), contoured at zero by OpenVDB's volumeToMesh (quads split in two), facing
// outward. The result is closed and free of self-intersections whatever the input's were (a
// scanned mesh's folds are resolved by the level set's inside/outside), at the price of detail
// below the voxel size. InputError as write_vdb_from_surface.
SurfaceMesh remesh_through_level_set(const SurfaceMesh& surface, double voxel_size, const Progress& progress = {});

// The triangles of a tetrahedral mesh's boundary (faces used by one cell), facing outward.
SurfaceMesh boundary_surface(const TetMesh& mesh);

}  // namespace prismoid::io
