#pragma once
// Small files for the bad-input tests (issue 18), written from their bytes: a binary PLY cube
// (VTK's PLY reader crashes on it truncated), a legacy ASCII ball, and a .vtu whose cell array
// is shorter than its cells (VTK's XML reader reads past its end).
#include <sstream>
#include <string>

#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::test {

// The unit cube as a binary PLY surface (8 vertices, 12 triangles), VTK's PLY reader's input.
inline std::string cube_ply() {
  std::string s =
      "ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 12\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 8; ++i) {
    const float p[3] = {float(i & 1), float((i >> 1) & 1), float((i >> 2) & 1)};
    s.append(reinterpret_cast<const char*>(p), sizeof p);
  }
  const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                            {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : faces) {
    s.push_back(char(3));
    s.append(reinterpret_cast<const char*>(f), sizeof f);
  }
  return s;
}

// A legacy ASCII unstructured grid: the ball's tetrahedra with the cell array "extinction" = 1.
inline std::string ball_legacy_vtk() {
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 2, 1.0);
  std::ostringstream s;
  s.precision(17);
  s << "# vtk DataFile Version 3.0\nball\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS " << ball.points.size() << " double\n";
  for (const auto& p : ball.points) s << p.x << " " << p.y << " " << p.z << "\n";
  s << "CELLS " << ball.tets.size() << " " << 5 * ball.tets.size() << "\n";
  for (const auto& t : ball.tets) s << "4 " << t[0] << " " << t[1] << " " << t[2] << " " << t[3] << "\n";
  s << "CELL_TYPES " << ball.tets.size() << "\n";
  for (size_t i = 0; i < ball.tets.size(); ++i) s << "10\n";
  s << "CELL_DATA " << ball.tets.size() << "\nSCALARS extinction double 1\nLOOKUP_TABLE default\n";
  for (size_t i = 0; i < ball.tets.size(); ++i) s << "1\n";
  return s.str();
}

// Two tetrahedra whose cell array holds one value: VTK's XML reader read past its end.
inline const char* const kShortArrayVtu = R"(<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">
  <UnstructuredGrid>
    <Piece NumberOfPoints="5" NumberOfCells="2">
      <CellData>
        <DataArray type="Float64" Name="extinction" format="ascii">1</DataArray>
      </CellData>
      <Points>
        <DataArray type="Float64" NumberOfComponents="3" format="ascii">0 0 0 1 0 0 0 1 0 0 0 1 1 1 1</DataArray>
      </Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">0 1 2 3 1 2 3 4</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">4 8</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">10 10</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
)";

}  // namespace prismoid::test
