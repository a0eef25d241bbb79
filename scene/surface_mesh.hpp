#pragma once
// A triangle surface as plain data: what io reads from .vtp/.stl/.obj/.ply/.off files.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace prismoid {

struct SurfaceMesh {
  std::string name;
  std::vector<glm::dvec3> points;
  std::vector<std::array<uint32_t, 3>> triangles;
};

}  // namespace prismoid
