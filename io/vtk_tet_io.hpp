#pragma once
// Tetrahedral meshes from VTK files (.vtu XML and legacy .vtk unstructured grids), through
// VTK's own readers. VTK types stay inside io/: callers get a plain TetMesh.
#include <string>

#include "scene/tet_mesh.hpp"

namespace prismoid::io {

struct TetReadOptions {
  // Array that gives the extinction (vectors by magnitude): a cell array makes sigma constant
  // per cell, a point array makes it linear in each cell. Empty: sigma = 1 per cell.
  std::string array;
  double density_scale = 1.0;  // multiplies the array's values
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
