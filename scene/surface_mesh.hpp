#pragma once
// A triangle surface as plain data: what io reads from .vtp/.stl/.obj/.ply/.off files.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace prismoid {

// A numeric data array of a surface file: `components` values per tuple, one tuple per point
// or per triangle.
struct SurfaceArray {
  std::string name;
  uint32_t components = 1;
  std::vector<double> values;  // tuple after tuple
};

struct SurfaceMesh {
  std::string name;
  std::vector<glm::dvec3> points;
  std::vector<std::array<uint32_t, 3>> triangles;
  std::vector<SurfaceArray> point_arrays;  // one tuple per point
  std::vector<SurfaceArray> cell_arrays;   // one tuple per triangle (a polygon's value on each of its triangles)
};

}  // namespace prismoid
