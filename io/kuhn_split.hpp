#pragma once
// The Kuhn split of a voxel cell (the box between 8 neighbouring voxel centres) into six
// tetrahedra: one per monotone path from corner 000 to corner 111 along the cell's edges. Every
// cell of a grid is split the same way, so the diagonals of shared faces agree and a mesh of such
// cells is conforming. Shared by the image volumes and the OpenVDB grids.
#include <array>
#include <cstdint>

namespace prismoid::io {

// A cell's corner number: bit a set means one step along index axis a (corner 0 is the cell's
// lowest index, corner 7 its highest).
constexpr uint32_t kuhn_corner(uint32_t x, uint32_t y, uint32_t z) { return x | (y << 1) | (z << 2); }

namespace detail {
// Path (p0, p1, p2) gives the tetrahedron 0, e_p0, e_p0 + e_p1, 7, whose edge vectors from corner
// 0 have determinant sign(permutation p); odd permutations swap their last two corners so every
// tetrahedron is positively oriented in index space.
constexpr std::array<std::array<uint8_t, 4>, 6> make_kuhn_tets() {
  constexpr int kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  constexpr bool kOdd[6] = {false, true, true, false, false, true};
  std::array<std::array<uint8_t, 4>, 6> tets{};
  for (int p = 0; p < 6; ++p) {
    const uint8_t first = uint8_t(1u << kPaths[p][0]);
    const uint8_t second = uint8_t(first | (1u << kPaths[p][1]));
    tets[size_t(p)] = kOdd[p] ? std::array<uint8_t, 4>{0, first, 7, second} : std::array<uint8_t, 4>{0, first, second, 7};
  }
  return tets;
}
}  // namespace detail

// The six tetrahedra as corner numbers, positively oriented when the grid's index axes map to a
// right-handed frame (swap the last two corners of each when they do not).
inline constexpr std::array<std::array<uint8_t, 4>, 6> kKuhnTets = detail::make_kuhn_tets();

}  // namespace prismoid::io
