#pragma once
// Triangle surfaces from files, and their tetrahedralization with TetGen (Si 2015, the Debian
// library libtet). VTK and TetGen types never leave io/.
#include <cstdint>
#include <string>

#include "io/progress.hpp"
#include "scene/surface_mesh.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::io {

// .vtp (VTK XML polydata), .stl, .obj, .ply through VTK's readers; .off (Object File Format)
// through our own small reader, since VTK 9.1 has none. Polygons are split into triangles and
// coincident points merged (STL stores each triangle's corners separately). InputError naming
// the file for a missing, unreadable or empty file. `progress` sees VTK's reading and cleaning
// (fractions rising to 1); returning false cancels (Cancelled).
bool is_surface_path(const std::string& path);
SurfaceMesh read_surface(const std::string& path, const Progress& progress = {});

// Edges used by one triangle (holes) or by more than two (non-manifold).
struct SurfaceCheck {
  size_t boundary_edges = 0;
  size_t nonmanifold_edges = 0;
  glm::dvec3 first_problem{0.0};  // a point on the first such edge
  bool closed() const { return boundary_edges == 0 && nonmanifold_edges == 0; }
};
SurfaceCheck check_surface(const SurfaceMesh& surface);

// Closes holes with VTK's vtkFillHolesFilter (each hole becomes a triangulated patch).
SurfaceMesh fill_holes(const SurfaceMesh& surface);

struct TetgenOptions {
  double radius_edge_ratio = 1.414;  // TetGen -q: quality bound (smaller: rounder cells, more of them)
  double max_volume = 0.0;           // TetGen -a: largest cell volume; 0: no bound
  // About this many tetrahedra (0: no target; then max_volume must be 0): the volume bound starts
  // at the enclosed volume / target_cells and is corrected from the count TetGen returns (quality
  // refinement adds cells), at most twice, until the count is within kTargetCellsTolerance.
  uint64_t target_cells = 0;
};
inline constexpr double kTargetCellsTolerance = 0.15;  // relative

// The volume a closed, consistently wound surface encloses (divergence theorem; positive for
// outward-facing triangles, negative for inward).
double enclosed_volume(const SurfaceMesh& surface);

// A constrained Delaunay tetrahedralization of the closed surface's interior, extinction 1 per
// cell. InputError(surface.name, ...) for open or non-manifold surfaces (saying where, and that
// --fill-holes exists) and for what TetGen rejects (self-intersections, tiny features).
// `progress` is called about ten times a second while TetGen runs (fraction -1: unknown);
// returning false stops TetGen and throws Cancelled.
TetMesh tetrahedralize(const SurfaceMesh& surface, const TetgenOptions& options, const Progress& progress = {});

// A surface file filled with tetrahedra, through a cache: the result is stored as .vtu under
// `cache_dir` (default $XDG_CACHE_HOME/prismoid, else ~/.cache/prismoid) keyed by a hash of the
// file's bytes and the options, so reopening the same file with the same options skips TetGen.
// A cache that cannot be written is skipped, not an error.
struct SurfaceToTets {
  TetgenOptions tetgen;
  bool fill_holes = false;
  // > 0: replace the surface (after hole filling) by its level set's zero crossing at this voxel
  // size (remesh_through_level_set in io/vdb_io.hpp) before TetGen: for self-intersecting scans.
  double remesh_voxel_size = 0.0;
  std::string cache_dir;  // empty: the default above
  Progress progress;      // passed to read_surface and tetrahedralize
};
struct SurfaceTets {
  TetMesh mesh;
  size_t triangles = 0;     // of the surface (0 when it came from the cache)
  bool from_cache = false;
  std::string cache_file;   // where the result is (or would have been) stored
};
SurfaceTets surface_to_tets(const std::string& path, const SurfaceToTets& options);

}  // namespace prismoid::io
