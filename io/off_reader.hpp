#pragma once
// OFF (Object File Format), which VTK 9.1 cannot read: "OFF", then vertex, face and edge counts,
// the vertices, then each face as its vertex count and indices. Comments (#) and blank lines are
// skipped. Plain C++ (no VTK), so the fuzz targets can link it. Internal to io/.
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace prismoid::io::detail {

struct OffPolygons {
  std::vector<glm::dvec3> points;
  std::vector<std::vector<uint32_t>> faces;  // polygons, as read; every index < points.size()
};

// Throws InputError(name, ...) for a missing "OFF" header, a file that ends early, a token that
// is not a number, a non-finite coordinate, a count out of range or a vertex index past the end.
OffPolygons parse_off(std::istream& in, const std::string& name);

}  // namespace prismoid::io::detail
