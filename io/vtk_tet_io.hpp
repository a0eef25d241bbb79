#pragma once
// Tetrahedral meshes from VTK unstructured grids (.vtu, legacy .vtk, multiblock .vtm, parallel
// .pvtu) and Exodus II files (io/exodus_io.hpp), through VTK's own readers and filters. VTK types stay inside io/: callers get a plain
// TetMesh and, if they ask, a report of what reading did to the file's cells.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "io/progress.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::io {

// What the chosen array means.
enum class ArrayRole {
  Extinction,  // the array's values (times density_scale) are sigma; must be >= 0
  Scalars,     // a scalar field for a transfer function; any finite values
};

// Each subdivision level multiplies a higher-order cell's tetrahedra by about 8.
constexpr uint32_t kMaxSubdivision = 5;

struct TetReadOptions {
  // The array to use (vectors by magnitude): a cell array is constant per cell, a point array
  // linear in each cell. Empty: sigma = density_scale per cell; as Scalars, the array ParaView
  // would colour by (MeshConversion::chosen_array says which), else no scalar field.
  std::string array;
  int component = -1;  // of a vector array; -1: its magnitude
  ArrayRole role = ArrayRole::Extinction;
  double density_scale = 1.0;  // multiplies the array's values (Extinction role only)
  // The blocks drawn: an Exodus II file's element blocks, each by its id or its name (empty:
  // every block that holds 3D cells); a .vtm's blocks, each by its index or its name (empty:
  // every unstructured grid block). An Exodus II file's time step (an index, 0 the first).
  std::vector<std::string> blocks;
  uint32_t time_step = 0;
  // Higher-order cells (quadratic, Lagrange, Bezier): 0 splits them through their nodes, as every
  // cell is split; N in 1..kMaxSubdivision tessellates them with VTK's vtkTessellatorFilter, each
  // edge halved up to N times wherever the cell's shape or a point array is not linear along it
  // (the new points get the cell's own interpolation of position and point arrays).
  uint32_t subdivision = 0;
  // Called while VTK reads and splits cells (fractions rise to 1); returning false cancels:
  // read_tet_mesh then throws Cancelled.
  Progress progress;
};

// What reading did to the file's cells. 3D cells other than tetrahedra (hexahedra, voxels,
// wedges, pyramids, pentagonal/hexagonal prisms, quadratic and higher-order cells) are split by
// VTK's vtkDataSetTriangleFilter: an ordered triangulation keyed on global point ids, so
// neighbouring cells split their shared faces the same way (conforming, no cracks; pieces of a
// .vtm/.pvtu are merged first so that they share ids). Quadratic cells are split through all
// their nodes (mid-edge nodes become tetrahedron corners): a curved cell becomes piecewise
// linear. Polyhedra (VTK_POLYHEDRON) go through their own Triangulate(), which VTK does not
// document as conforming. Cell arrays are copied to each cell's tetrahedra; points and point
// arrays are kept. Cells wound as VTK defines them give positively oriented tetrahedra.
struct MeshConversion {
  std::map<std::string, size_t> cells_in;  // the file's cells by VTK class name, e.g. vtkHexahedron
  size_t dropped = 0;        // of those, cells without volume (2D, 1D, vertices): not drawn
  size_t tets_out = 0;
  size_t pieces = 1;         // blocks (.vtm) or pieces (.pvtu) merged into one mesh
  size_t merged_points = 0;  // points shared between pieces, stored once after merging
  size_t zero_volume = 0;    // flat tetrahedra, kept: they contribute nothing
  size_t inverted = 0;       // negative orientation, kept as they are: rendering ignores orientation
  // With no array named and the Scalars role, the array picked as ParaView picks one: the
  // active point scalars, else the active cell scalars, else the only point array, else the
  // only cell array, an array named "extinction" (what Prismoid writes) aside. Empty: none.
  std::string chosen_array;
  std::string chosen_why;    // e.g. "the only point array"
  // What the file holds that is not drawn, one phrase each, e.g. "block 30 (vtkQuad): no 3D cells".
  std::vector<std::string> ignored;
  size_t higher_order = 0;    // 3D cells of quadratic, Lagrange or Bezier type
  uint32_t subdivision = 0;   // the level they were tessellated at (TetReadOptions::subdivision)
  bool split() const;        // whether any cell was not a tetrahedron
};

// One line for the user, e.g. "split 8 vtkHexahedron into 40 tetrahedra; 2 inverted
// tetrahedra (rendered as they are)"; empty when the file held only sound tetrahedra.
std::string conversion_note(const MeshConversion& conversion);

// Throws InputError naming the file and the problem: missing, unreadable, truncated or
// corrupt file, not a VTK unstructured grid, a .vtm block that is not one, no 3D cells,
// point indices out of range, an unknown array (the message lists the ones there are),
// negative or non-finite values. `conversion`, when given, receives the report above.
TetMesh read_tet_mesh(const std::string& path, const TetReadOptions& options = {}, MeshConversion* conversion = nullptr);

// Writes the mesh as a .vtu with its extinction as the cell array `extinction` (and the
// point scalars, if any, as the point array `scalars`). Writes `path` itself (a failed write
// removes it; putting the file in place whole is the caller's, app/common/output_files.hpp).
// InputError when it cannot write.
void write_tet_mesh_vtu(const std::string& path, const TetMesh& mesh);

// Whether `path` has an extension read_tet_mesh understands.
bool is_tet_mesh_path(const std::string& path);
// Whether `path` names a multiblock .vtm (its blocks are chosen with TetReadOptions::blocks).
bool is_multiblock_path(const std::string& path);

}  // namespace prismoid::io
