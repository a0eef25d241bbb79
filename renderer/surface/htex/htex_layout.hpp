#pragma once
// Htex (Barbier & Dupuy 2022, "Htex: Per-Halfedge Texturing for Arbitrary Mesh Topologies",
// DOI 10.1145/3543868) laid out in one virtual atlas as Li & Guo ("Real-time Seamless Object
// Space Shading", section 3.1) do: plain data and math, no Vulkan. The GPU passes (pre-Z
// marking, allocation, shading, gather) address texels through this; the CPU reference
// (renderer/reference/htex_reference.hpp) blends them in double precision.
//
// Charts. Face f with centroid C is cut into three halfedge triangles (C, start(h), end(h)), one
// per halfedge h. A point there has local coordinates (u, v): P = (1 - u - v) C + u start(h) +
// v end(h), so the halfedge triangle is the unit right triangle u, v >= 0, u + v <= 1. The
// three charts of a face are joined by quarter turns about C (the face's chart is a 270 degree
// cone): next(h)'s chart holds the point at (v, -u) and prev(h)'s at (-v, u).
//
// Quads. Every edge e has one square texture on the unit square of quad coordinates (x, y).
// Its primary halfedge p (the larger id; see scene/halfedge_mesh.hpp) maps its halfedge triangle
// onto the half x + y <= 1 with (x, y) = (u, v); the twin t maps onto the other half with
// (x, y) = (1 - u, 1 - v). So (0, 0) is C of p's face, (1, 0) is start(p), (0, 1) is end(p),
// (1, 1) is C of t's face, and the diagonal x + y = 1 is the edge itself: bilinear filtering in
// the quad crosses the edge into the twin's face without any seam. A boundary edge has a half
// quad: texels wholly beyond the diagonal (i + j >= n + 1) are never read; the row i + j = n
// is read by filters reaching the boundary, and holds "ghost" texels whose points lie in the
// face's plane extended across the boundary by less than a texel.
//
// Texels. Quad side n = 2^k texels; texel (i, j) sits at (x, y) = ((i + 0.5) / n, (j + 0.5) / n).
// The two texels next to the quad's vertex corners, (n - 1, 0) at start(p) and (0, n - 1) at
// end(p), sit on the edge half a texel from the vertex. Htex is continuous across an edge only
// if every quad around a vertex holds the same value in that corner texel (Barbier & Dupuy's
// viewer averages them in a preprocessing pass, for displacement maps); here those texels are
// shaded at the vertex itself, in one canonical triangle of the vertex (canonical_corner), so
// all quads around it hold the same value by construction, whatever the shading depends on.
// That needs the two vertex corners of a quad to be distinct texels: n >= 2 at every level.
//
// Sizes (Li & Guo 3.1): all quads of a mesh have one size, chosen so that the largest quad
// gets the density asked for; smaller quads are then over-resolved in virtual space and the
// pre-Z pass picks a coarser level for them from screen-space derivatives. One size per mesh
// also keeps texel grids aligned across quad borders inside a face.
//
// Atlas. Each mesh's quads form, per mip level, a rectangle of quads in scan-line order
// (quad q at column q % columns, row q / columns), so a texel's position gives its quad by
// arithmetic. The rectangles of all meshes and levels are shelf-packed into one virtual
// texture; each starts on a shadel boundary (8 x 8 texels), so a shadel belongs to one
// rectangle. Shadel groups (8 x 8 shadels, Li & Guo 3.3) tile the atlas: its sides are
// multiples of 64 texels.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/halfedge_mesh.hpp"

namespace prismoid::htex {

inline constexpr uint32_t kShadelTexels = 8;  // a shadel is 8 x 8 texels (Baker & Jarzynski 2022)
inline constexpr uint32_t kGroupShadels = 8;  // a shadel group is 8 x 8 shadels (Li & Guo 3.3)
inline constexpr uint32_t kGroupTexels = kShadelTexels * kGroupShadels;

// ---- Charts -----------------------------------------------------------------------------------

// A point of a face in one of its halfedge triangles: halfedge h and local (u, v).
struct HalfedgePoint {
  int32_t halfedge = 0;
  glm::dvec2 uv{0.0};
};

// The halfedge triangle of `face` holding the point with barycentric weights `bary` (of the
// face's points p0, p1, p2) and its local coordinates there. On a border between two halfedge
// triangles either is returned; both give the same blend.
HalfedgePoint locate_in_face(uint32_t face, const glm::dvec3& bary);
// Inverse of locate_in_face: barycentric weights of the face's points for local (u, v) of
// halfedge h (a weight is negative when (u, v) lies outside the halfedge triangle's face).
glm::dvec3 face_barycentric(int32_t halfedge, const glm::dvec2& uv);

// Quad coordinates of halfedge h's local (u, v): (u, v) for a primary halfedge, 1 - (u, v) for
// its twin.
glm::dvec2 quad_coordinates(const HalfedgeMesh& mesh, int32_t halfedge, const glm::dvec2& uv);

// One quad sampled by the Htex lookup: edge id and quad coordinates (outside [0, 1]^2 for the
// quads of next(h) and prev(h) away from their shared border with h's triangle).
struct QuadPoint {
  uint32_t edge = 0;
  glm::dvec2 xy{0.0};
};
// The three quads a point of a face blends: those of h, next(h) and prev(h) for the halfedge
// triangle h that holds it, each at the point's coordinates in its chart.
std::array<QuadPoint, 3> face_point_quads(const HalfedgeMesh& mesh, uint32_t face, const glm::dvec3& bary);

// The surface point of quad coordinates (x, y) of edge `edge`: in the primary halfedge's face
// when x + y <= 1, else in the twin's face. On a boundary edge the half x + y > 1 has no face:
// the point is the primary face's plane extended (ghost = true, a barycentric weight < 0).
struct QuadSurfacePoint {
  uint32_t face = 0;
  glm::dvec3 bary{0.0};
  bool ghost = false;
};
QuadSurfacePoint quad_surface_point(const HalfedgeMesh& mesh, uint32_t edge, const glm::dvec2& xy);

// Where the texel (i, j) of a quad of side n is shaded (what the shading pass evaluates).
struct TexelPoint {
  uint32_t face = 0;
  glm::dvec3 bary{0.0};       // of the face's points; one weight < 0 for a ghost texel
  glm::dvec3 position{0.0};
  bool ghost = false;         // beyond a boundary edge, in the face's plane
  int32_t vertex = -1;        // >= 0: a vertex corner texel, shaded at this vertex
};
// The halfedge whose start corner a vertex-corner texel at vertex(h) is shaded in: the vertex's
// vertex_halfedge, one for all quads around the vertex (h itself if it has none).
int32_t canonical_corner(const HalfedgeMesh& mesh, int32_t h);
// snap_vertex_corners = false places the vertex corner texels at their nominal points, half a
// texel along the edge (what breaks continuity at vertices: for tests that show it).
TexelPoint texel_point(const HalfedgeMesh& mesh, uint32_t edge, uint32_t n, uint32_t i, uint32_t j,
                       bool snap_vertex_corners = true);

// How far a quad's chart stretches: the largest singular value of the maps from its (one or
// two) unit halfedge triangles to their 3D triangles, in world units per unit of quad
// coordinate. A texel of a quad of side n spans at most stretch / n in any direction.
double quad_stretch(const HalfedgeMesh& mesh, uint32_t edge);

// ---- Atlas ------------------------------------------------------------------------------------

struct LayoutOptions {
  double texels_per_unit = 64.0;  // level-0 texels per world unit on each mesh's largest quad
  uint32_t min_log2 = 1;          // quad side at level 0 is 2^log2 with log2 in [min_log2, max_log2]
  uint32_t max_log2 = 8;          //   (min_log2 is raised to 1: a side of 1 cannot be seamless)
};

struct MeshLayout {
  uint32_t first_quad = 0;   // global quad id of the mesh's edge 0 (quad = first_quad + edge)
  uint32_t quad_count = 0;   // the mesh's edge count
  uint32_t log2_side = 1;    // level-0 quad side 2^log2_side texels
  uint32_t levels = 1;       // mip levels 0 .. levels - 1, side 2^(log2_side - level) >= 2
  uint32_t columns = 1;      // quads per row in scan-line order
  uint32_t rows = 1;
  double largest_stretch = 0.0;    // the largest quad_stretch of the mesh
  std::vector<glm::uvec2> origin;  // per level: virtual texel of quad 0's texel (0, 0)
  uint32_t side(uint32_t level) const { return (1u << log2_side) >> level; }
  // Per level: the rectangle's size in texels, rounded up to whole shadels.
  glm::uvec2 extent(uint32_t level) const;
};

// A texel of the atlas named by its quad (global id), mip level and texel within the quad.
struct TexelAddress {
  uint32_t quad = 0;
  uint32_t level = 0;
  uint32_t i = 0, j = 0;
  bool operator==(const TexelAddress&) const = default;
};

class AtlasLayout {
 public:
  AtlasLayout(const std::vector<HalfedgeMesh>& meshes, const LayoutOptions& options = {});

  uint32_t width() const { return width_; }    // virtual texels, a multiple of kGroupTexels
  uint32_t height() const { return height_; }
  const std::vector<MeshLayout>& meshes() const { return meshes_; }
  uint32_t quad_count() const { return quad_count_; }
  uint32_t mesh_of_quad(uint32_t quad) const;

  // Quad texel -> virtual texel, and back (nullopt for padding: texels no quad owns).
  glm::uvec2 virtual_texel(const TexelAddress& texel) const;
  std::optional<TexelAddress> texel_at(const glm::uvec2& virtual_texel) const;

  // Shadels and shadel groups, numbered row by row over the atlas.
  uint32_t shadel_columns() const { return width_ / kShadelTexels; }
  uint32_t shadel_rows() const { return height_ / kShadelTexels; }
  uint32_t shadel_of(const glm::uvec2& virtual_texel) const {
    return (virtual_texel.y / kShadelTexels) * shadel_columns() + virtual_texel.x / kShadelTexels;
  }
  uint32_t group_of(const glm::uvec2& virtual_texel) const {
    return (virtual_texel.y / kGroupTexels) * (width_ / kGroupTexels) + virtual_texel.x / kGroupTexels;
  }
  // Which mesh and level own a shadel (-1 for none): the table the GPU reads to go from an
  // atlas position to its quad.
  struct Region {
    uint32_t mesh = 0, level = 0;
  };
  std::optional<Region> region_of_shadel(uint32_t shadel) const;

 private:
  std::vector<MeshLayout> meshes_;
  std::vector<Region> regions_;
  std::vector<int32_t> shadel_region_;  // per shadel: index into regions_, or -1
  uint32_t width_ = 0, height_ = 0, quad_count_ = 0;
};

}  // namespace prismoid::htex
