#pragma once
// Exodus II files for the tests, written with the Exodus library VTK's reader itself uses
// (libvtk9-dev's vtkexodusII): blocks of any element type, element and nodal variables over
// time steps, node sets. Plain values in, a file out; what Prismoid reads back is then held to
// the values written.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::test {

struct ExodusBlockSpec {
  int64_t id = 1;
  std::string name;  // empty: none (VTK then calls it "Unnamed block ID: <id>")
  std::string type = "TETRA";  // the Exodus element type: TETRA, HEX8, QUAD4, TETRA10...
  int nodes_per_element = 4;
  std::vector<int64_t> connectivity;  // 0-based point indices, nodes_per_element for each element
  std::vector<std::vector<std::vector<double>>> values;  // [step][element variable][element]; missing: zeros
  size_t elements() const { return connectivity.size() / size_t(nodes_per_element); }
};

struct ExodusFileSpec {
  std::vector<glm::dvec3> points;
  std::vector<ExodusBlockSpec> blocks;
  std::vector<double> times;  // the time steps' values, written as given (NaN and disorder included)
  std::vector<std::string> element_variables;
  std::vector<std::string> nodal_variables;
  std::vector<std::vector<std::vector<double>>> nodal_values;  // [step][nodal variable][point]
  std::vector<std::vector<int64_t>> node_sets;  // 0-based points of each
};

// Writes `spec` at `path` (replacing it); std::runtime_error naming the call that failed.
void write_exodus(const std::filesystem::path& path, const ExodusFileSpec& spec);

// The points and one TETRA block of `mesh` (its tetrahedra as they are).
ExodusFileSpec exodus_of(const TetMesh& mesh, int64_t block_id = 1);

}  // namespace prismoid::test
