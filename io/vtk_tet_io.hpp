#pragma once
// Tetrahedral meshes from VTK files (.vtu XML and legacy .vtk unstructured grids), through
// VTK's own readers. VTK types stay inside io/: callers get a plain TetMesh.
#include <string>

#include "scene/tet_mesh.hpp"

namespace prismoid::io {

// What the chosen array means.
enum class ArrayRole {
  Extinction,  // the array's values (times density_scale) are sigma; must be >= 0
  Scalars,     // a scalar field for a transfer function; any finite values
};

struct TetReadOptions {
  // The array to use (vectors by magnitude): a cell array is constant per cell, a point array
  // linear in each cell. Empty: sigma = density_scale per cell, and no scalar field.
  std::string array;
  ArrayRole role = ArrayRole::Extinction;
  double density_scale = 1.0;  // multiplies the array's values (Extinction role only)
};

// Throws InputError naming the file and the problem: missing or unreadable file, not a VTK
// unstructured grid, cells that are not tetrahedra (conversion arrives with the data layer),
// an unknown array (the message lists the ones there are), negative or non-finite values.
TetMesh read_tet_mesh(const std::string& path, const TetReadOptions& options = {});

// Writes the mesh as a .vtu with its extinction as the cell array `extinction` (and the
// point scalars, if any, as the point array `scalars`). InputError when it cannot write.
void write_tet_mesh_vtu(const std::string& path, const TetMesh& mesh);

// Whether `path` has an extension read_tet_mesh understands.
bool is_tet_mesh_path(const std::string& path);

}  // namespace prismoid::io
