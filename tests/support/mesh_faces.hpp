#pragma once
// How many tetrahedra use each triangle of a mesh, by its sorted point indices: 2 for an
// interior face of a conforming mesh, 1 on its boundary; anything else is a crack or an overlap.
#include <algorithm>
#include <array>
#include <cstdint>
#include <map>

#include "scene/tet_mesh.hpp"

namespace prismoid::test {

inline std::map<std::array<uint32_t, 3>, int> face_uses(const TetMesh& mesh) {
  std::map<std::array<uint32_t, 3>, int> uses;
  for (const auto& t : mesh.tets)
    for (size_t skip = 0; skip < 4; ++skip) {
      std::array<uint32_t, 3> f{};
      for (size_t k = 0, n = 0; k < 4; ++k)
        if (k != skip) f[n++] = t[k];
      std::sort(f.begin(), f.end());
      ++uses[f];
    }
  return uses;
}

}  // namespace prismoid::test
