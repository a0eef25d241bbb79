#include "support/exodus_file.hpp"

#include <stdexcept>

#include <vtk_exodusII.h>

#include "scene/tet_mesh.hpp"

namespace prismoid::test {

namespace {

void check(int status, const std::string& call, const std::filesystem::path& path) {
  if (status < 0) throw std::runtime_error(path.string() + ": " + call + " failed (" + std::to_string(status) + ")");
}

// The Exodus library takes names as a mutable char* array.
std::vector<char*> name_pointers(std::vector<std::string>& names) {
  std::vector<char*> pointers;
  for (std::string& n : names) pointers.push_back(n.data());
  return pointers;
}

}  // namespace

void write_exodus(const std::filesystem::path& path, const ExodusFileSpec& spec) {
  int word = 8, io_word = 8;  // doubles in memory and in the file
  const int exo = ex_create(path.c_str(), EX_CLOBBER, &word, &io_word);
  if (exo < 0) throw std::runtime_error(path.string() + ": ex_create failed");
  size_t elements = 0;
  for (const ExodusBlockSpec& b : spec.blocks) elements += b.elements();
  check(ex_put_init(exo, "prismoid test", 3, int64_t(spec.points.size()), int64_t(elements), int64_t(spec.blocks.size()),
                    int64_t(spec.node_sets.size()), 0),
        "ex_put_init", path);
  std::vector<double> x, y, z;
  for (const glm::dvec3& p : spec.points) x.push_back(p.x), y.push_back(p.y), z.push_back(p.z);
  check(ex_put_coord(exo, x.data(), y.data(), z.data()), "ex_put_coord", path);
  for (const ExodusBlockSpec& b : spec.blocks) {
    check(ex_put_block(exo, EX_ELEM_BLOCK, b.id, b.type.c_str(), int64_t(b.elements()), b.nodes_per_element, 0, 0, 0), "ex_put_block", path);
    std::vector<int> connectivity;  // 1-based
    for (int64_t i : b.connectivity) connectivity.push_back(int(i + 1));
    check(ex_put_conn(exo, EX_ELEM_BLOCK, b.id, connectivity.data(), nullptr, nullptr), "ex_put_conn", path);
    if (!b.name.empty()) check(ex_put_name(exo, EX_ELEM_BLOCK, b.id, b.name.c_str()), "ex_put_name", path);
  }
  for (size_t s = 0; s < spec.node_sets.size(); ++s) {
    const int64_t id = int64_t(s + 1);
    check(ex_put_set_param(exo, EX_NODE_SET, id, int64_t(spec.node_sets[s].size()), 0), "ex_put_set_param", path);
    std::vector<int> nodes;
    for (int64_t i : spec.node_sets[s]) nodes.push_back(int(i + 1));
    check(ex_put_set(exo, EX_NODE_SET, id, nodes.data(), nullptr), "ex_put_set", path);
  }
  std::vector<std::string> nodal = spec.nodal_variables, element = spec.element_variables;
  if (!nodal.empty()) {
    check(ex_put_variable_param(exo, EX_NODAL, int(nodal.size())), "ex_put_variable_param", path);
    check(ex_put_variable_names(exo, EX_NODAL, int(nodal.size()), name_pointers(nodal).data()), "ex_put_variable_names", path);
  }
  if (!element.empty()) {
    check(ex_put_variable_param(exo, EX_ELEM_BLOCK, int(element.size())), "ex_put_variable_param", path);
    check(ex_put_variable_names(exo, EX_ELEM_BLOCK, int(element.size()), name_pointers(element).data()), "ex_put_variable_names", path);
  }
  for (size_t s = 0; s < spec.times.size(); ++s) {
    const int step = int(s + 1);  // Exodus counts steps from 1
    check(ex_put_time(exo, step, &spec.times[s]), "ex_put_time", path);
    for (size_t v = 0; v < nodal.size(); ++v) {
      std::vector<double> values(spec.points.size(), 0.0);
      if (s < spec.nodal_values.size() && v < spec.nodal_values[s].size()) values = spec.nodal_values[s][v];
      check(ex_put_var(exo, step, EX_NODAL, int(v + 1), 1, int64_t(values.size()), values.data()), "ex_put_var", path);
    }
    for (const ExodusBlockSpec& b : spec.blocks)
      for (size_t v = 0; v < element.size(); ++v) {
        std::vector<double> values(b.elements(), 0.0);
        if (s < b.values.size() && v < b.values[s].size()) values = b.values[s][v];
        check(ex_put_var(exo, step, EX_ELEM_BLOCK, int(v + 1), b.id, int64_t(values.size()), values.data()), "ex_put_var", path);
      }
  }
  check(ex_close(exo), "ex_close", path);
}

ExodusFileSpec exodus_of(const TetMesh& mesh, int64_t block_id) {
  ExodusFileSpec spec;
  spec.points = mesh.points;
  ExodusBlockSpec block;
  block.id = block_id;
  for (const auto& t : mesh.tets)
    for (int k = 0; k < 4; ++k) block.connectivity.push_back(int64_t(t[k]));
  spec.blocks.push_back(block);
  return spec;
}

}  // namespace prismoid::test
