#pragma once
// Exodus II files (.exo .e .ex2 .exii .g .gen: the output of Sandia's and many finite-element
// codes), read by VTK's vtkExodusIIReader in a reader child (io/isolated_read.hpp), as ParaView
// reads them: element blocks with their nodal and element variables at one time step, nodal
// displacements applied where the file has them (a vector variable named DISPL or similar, as
// ParaView applies them by default). Side sets, node sets, face and edge blocks are not drawn.
//
// Drawing one goes through read_tet_mesh (io/vtk_tet_io.hpp) like any mesh file:
// TetReadOptions::blocks picks blocks, ::time_step the step; the chosen blocks are merged into
// one mesh with their coincident nodes shared, as a .vtm's blocks are.
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace prismoid::io {

struct ExodusBlock {
  int64_t id = 0;         // the file's block id
  std::string name;       // the file's name for it, or VTK's "Unnamed block ID: N"
  std::string cell_type;  // VTK's class of its cells, e.g. vtkHexahedron; empty for an empty block
  size_t cells = 0;
  bool solid = false;     // holds 3D cells: drawn by default
};
template <typename S, typename M>
  requires std::is_same_v<std::remove_const_t<M>, ExodusBlock>
void fields(S& s, M& b) {
  s(b.id);
  s(b.name);
  s(b.cell_type);
  s(b.cells);
  s(b.solid);
}

struct ExodusInfo {
  std::vector<ExodusBlock> blocks;  // element blocks, in the file's order
  std::vector<std::string> nodal_variables;    // point arrays when drawn
  std::vector<std::string> element_variables;  // cell arrays when drawn
  std::vector<double> times;  // one per time step, increasing; empty: the file holds no steps
  size_t node_sets = 0, side_sets = 0;  // not drawn
};

// Whether `path` has an Exodus II extension.
bool is_exodus_path(const std::string& path);

// The file's blocks, variables, time values and sets; with `cells`, the blocks' cells are read
// (at the first step, without variables) for their type, else ExodusBlock::cell_type and ::solid
// stay unset. InputError naming the file for: not an Exodus II file VTK can read, a truncated
// or corrupt one, time values that are not finite or do not increase.
ExodusInfo read_exodus_info(const std::string& path, bool cells = true);

// "10 'fluid'" or "20" (a block VTK names "Unnamed block ID: 20" is said by its id alone).
std::string block_label(const ExodusBlock& block);

}  // namespace prismoid::io
