#pragma once
// Walking between Htex texels across the surface (plain math, no Vulkan): the spatial
// neighbourhood ReSTIR GI in object space draws from (Li & Guo 4.1: neighbours by the mesh's
// adjacency, not by a UV map, so the walk has no seams).
//
// All quads of a mesh have one side n at a given level (htex_layout.hpp), so texel grids line up
// across every quad border: the quarter turns between a face's three halfedge charts and the
// flip between a quad's two halves (x, y) -> (1 - x, 1 - y) map texel centres onto texel
// centres. A unit step from texel (i, j) of edge e's quad goes to (i +- 1, j) or (i, j +- 1);
// where that leaves the unit square it continues in the chart beyond the side it crossed:
//   x < 0 (side C(p) - end(p), in p's half)   -> next(p)'s chart,
//   y < 0 (side C(p) - start(p), in p's half) -> prev(p)'s chart,
//   x > 1 (in the twin t's half)              -> next(t)'s chart,
//   y > 1 (in the twin t's half)              -> prev(t)'s chart,
// with chart texel maps (a, b) -> (b, -1 - a) into next(h) and (a, b) -> (-1 - b, a) into prev(h)
// (the texel-centre form of htex_layout.hpp's (u, v) -> (v, -u) and (-v, u)). Directions turn
// with the same linear maps, so a walk keeps going "straight" across borders. Steps that leave
// the surface (across a boundary edge) or land on a ghost texel (the half beyond a boundary
// edge) fail. Around a face's centre the charts form a 270 degree cone and around a vertex any
// angle: a walk there is well defined step by step, but a walk and its reverse need not meet
// (as on any cone); single steps always reverse exactly.
#include <cstdint>
#include <optional>

#include <glm/vec2.hpp>

#include "scene/halfedge_mesh.hpp"

namespace prismoid::htex {

// Texel (i, j) of edge `edge`'s quad (side n, known from the context).
struct QuadTexel {
  uint32_t edge = 0;
  int32_t i = 0, j = 0;
  bool operator==(const QuadTexel&) const = default;
};

// A 2 x 2 integer map of directions (columns: images of (1, 0) and (0, 1)).
struct DirectionMap {
  glm::ivec2 x{1, 0}, y{0, 1};
  glm::ivec2 operator()(const glm::ivec2& d) const { return d.x * x + d.y * y; }
};

// True for a ghost texel: beyond a boundary edge (i + j >= n in a quad without twin).
bool is_ghost_texel(const HalfedgeMesh& mesh, uint32_t n, const QuadTexel& texel);

struct TexelStep {
  QuadTexel texel;
  DirectionMap turn;  // directions in the old quad's (i, j) frame -> the new quad's
};
// One unit step from a valid texel along `direction` ((+-1, 0) or (0, +-1)); nullopt where it
// leaves the surface or lands on a ghost texel. Throws std::invalid_argument for another direction.
std::optional<TexelStep> step_texel(const HalfedgeMesh& mesh, uint32_t n, const QuadTexel& from, const glm::ivec2& direction);

// |offset.x| unit steps along the start quad's i axis, then |offset.y| along its j axis, each
// axis carried through the charts the walk crosses. nullopt where a step fails.
std::optional<QuadTexel> walk_texel(const HalfedgeMesh& mesh, uint32_t n, const QuadTexel& from, const glm::ivec2& offset);

}  // namespace prismoid::htex
