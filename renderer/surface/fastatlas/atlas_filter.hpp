#pragma once
// FastAtlas's hard-edge filter at lookup (Real-Time Compact Atlases for Texture Space Shading,
// appendix A), on the CPU: the rule the atlas lookup shader is to follow, and its twin in tests.
// A bilinear lookup near a chart's crease would blend shading from across it (a sharp edge of the
// surface, or another triangle packed next to it in the atlas). So each of the four taps counts
// only when its texel was shaded for the fragment's own triangle, or for a neighbour meeting it
// at a dihedral angle under a threshold (75 degrees in the paper); the value is rebuilt from the
// taps that count:
//   0: the nearest texel (nothing better is known), or where it holds no triangle the first tap
//      that holds one (a triangle too small for a texel of its own at a low scale);   1: that texel;
//   2: linear interpolation between them, at the sample's projection onto the line through them;
//   3: barycentric interpolation over their triangle (Sen, Shadow silhouette maps), clamped
//      per channel to the three values, since outside the triangle it would extrapolate;
//   4: bilinear.
#include <array>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace prismoid::fastatlas {

// Taps in bilinear order: (0, 0), (1, 0), (0, 1), (1, 1) in texel steps from the first.
struct FilterTaps {
  std::array<glm::dvec3, 4> value;
  std::array<bool, 4> usable{};
  std::array<bool, 4> held{true, true, true, true};  // the texel holds a triangle (shaded)
};

// The filtered value at `at` = (fx, fy) in [0, 1]^2, the sample's place between the four taps.
glm::dvec3 hard_edge_filter(const FilterTaps& taps, const glm::dvec2& at);

// Whether a tap shaded for a triangle with unit normal `tap_normal` may stand for the fragment's
// triangle with unit normal `own_normal`: the same triangle, or an edge neighbour whose normal
// turns by less than `max_degrees` (the dihedral angle's supplement: 0 on a flat surface).
bool tap_usable(bool same_triangle, bool edge_neighbour, const glm::dvec3& own_normal, const glm::dvec3& tap_normal,
                double max_degrees = 75.0);

}  // namespace prismoid::fastatlas
