// A test fixture program: a tetrahedral mesh's point array as the nodal variable of an Exodus II
// file over time steps, for tests that open Exodus files in other programs (the ParaView plugin's:
// pvpython cannot write Exodus). Written with the Exodus library VTK's reader uses.
//   write_exodus_steps IN.vtu ARRAY OUT.exo TIME:SCALE...
// Step i is at TIME_i, the array's values times SCALE_i.
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>

#include "io/isolated_read.hpp"
#include "io/vtk_tet_io.hpp"
#include "scene/tet_mesh.hpp"
#include "support/exodus_file.hpp"

int main(int argc, char** argv) {
  prismoid::io::serve_isolated_child(argc, argv);  // read_tet_mesh reads in a child process
  if (argc < 5) {
    std::cerr << "usage: write_exodus_steps IN.vtu ARRAY OUT.exo TIME:SCALE...\n";
    return 2;
  }
  try {
    prismoid::io::TetReadOptions reading;
    reading.array = argv[2];
    reading.role = prismoid::io::ArrayRole::Scalars;
    const prismoid::TetMesh mesh = prismoid::io::read_tet_mesh(argv[1], reading);
    if (mesh.point_scalars.empty()) throw std::runtime_error(std::string(argv[2]) + " is not a point array of " + argv[1]);
    prismoid::test::ExodusFileSpec spec = prismoid::test::exodus_of(mesh);
    spec.nodal_variables = {argv[2]};
    for (int i = 4; i < argc; ++i) {
      const std::string pair = argv[i];
      const size_t colon = pair.find(':');
      if (colon == std::string::npos) throw std::runtime_error("'" + pair + "' is not TIME:SCALE");
      spec.times.push_back(std::stod(pair.substr(0, colon)));
      const double scale = std::stod(pair.substr(colon + 1));
      std::vector<double> values = mesh.point_scalars;
      for (double& v : values) v *= scale;
      spec.nodal_values.push_back({values});
    }
    prismoid::test::write_exodus(argv[3], spec);
  } catch (const std::exception& e) {
    std::cerr << "write_exodus_steps: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
