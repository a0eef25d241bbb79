#pragma once
// The Htex lookup in double precision: what the GPU gather is tested against.
//
// A point of a face blends the quads of its halfedge triangle's three halfedges
// (htex::face_point_quads). Each quad is read with bilinear filtering and a zero border, and
// with the same filter over an all-ones texture of its size (its alpha mask):
//   alpha_q(x, y) = a_n(x) a_n(y),  a_n(t) = clamp(min(n t, n (1 - t)) + 1/2, 0, 1),
// so a quad fades from 1 to 0 over the half texel either side of its border. The value is
// sum_q (bilinear colour_q) / sum_q alpha_q (Barbier & Dupuy 2022; their Htex.glsl divides the
// three colour fetches by the three alpha fetches). That makes it a normalized sum over at most
// 12 texels (4 per quad) with non-negative weights summing to 1; inside its own halfedge
// triangle a quad's alpha is at least 1/4, so the divisor never falls below 1/4.
//
// Why it is continuous (what the tests check numerically):
//  - inside a face: the three charts are joined by quarter turns; a quad's weights and texels
//    are the same whichever halfedge triangle of the face the point is located in;
//  - across an edge: both faces read the edge's quad at the same quad coordinates (the twin's
//    are 1 - (u, v)); the face's other quads reach the edge only within half a texel of its
//    ends, where they read just their vertex corner texels, and those all hold the value shaded
//    at the vertex (htex::texel_point).
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/surface/htex/htex_layout.hpp"
#include "scene/halfedge_mesh.hpp"

namespace prismoid::reference {

// One texel read by a lookup, with its normalized weight.
struct HtexTexelWeight {
  htex::TexelAddress texel;  // global quad id
  double weight = 0.0;
};

// Every texel a lookup reads (weight > 0), at most 12.
struct HtexFootprint {
  std::array<HtexTexelWeight, 12> texels{};
  uint32_t count = 0;
  double alpha = 0.0;  // sum of the three alpha masks: the divisor
};

// The normalized weights of the Htex lookup at a point of face `face` of mesh `mesh` (index
// into the layout) with barycentric weights `bary`, at mip level `level`.
HtexFootprint htex_footprint(const std::vector<HalfedgeMesh>& meshes, const htex::AtlasLayout& layout, uint32_t mesh,
                             uint32_t face, const glm::dvec3& bary, uint32_t level);

// Level of detail for a point of a face whose barycentric weights change by dbary_dx and
// dbary_dy per pixel: log2(n * max(|d(u,v)/dx|, |d(u,v)/dy|)) in the local chart of its
// halfedge triangle (all three quads' coordinates are turns or reflections of it, so they
// agree), not clamped: the caller clamps to [0, levels - 1].
double htex_level_of_detail(const htex::MeshLayout& layout, uint32_t face, const glm::dvec3& bary, const glm::dvec3& dbary_dx,
                            const glm::dvec3& dbary_dy);

// The virtual shadels a lookup reads: what the pre-Z pass must mark for that pixel at that
// level (each listed once).
std::vector<uint32_t> htex_footprint_shadels(const htex::AtlasLayout& layout, const HtexFootprint& footprint);

// Texel values of every quad and level of an atlas, `channels` (1..4) doubles each.
class HtexTexture {
 public:
  HtexTexture(const htex::AtlasLayout& layout, uint32_t channels);
  uint32_t channels() const { return channels_; }
  glm::dvec4 get(const htex::TexelAddress& t) const;
  void set(const htex::TexelAddress& t, const glm::dvec4& value);

 private:
  size_t offset(const htex::TexelAddress& t) const;
  const htex::AtlasLayout* layout_;
  uint32_t channels_;
  std::vector<std::vector<size_t>> base_;  // per mesh, per level: index of quad 0's texel (0, 0)
  std::vector<double> values_;
};

// Shades every texel of every level: value = shade(mesh index, where the texel is shaded) —
// the job of the GPU's shading pass.
using HtexShader = std::function<glm::dvec4(uint32_t mesh, const htex::TexelPoint& point)>;
void htex_shade_all(const std::vector<HalfedgeMesh>& meshes, const htex::AtlasLayout& layout, const HtexShader& shade,
                    HtexTexture& texture, bool snap_vertex_corners = true);

// The blended value at a point (htex_footprint's weights times the texture's texels).
glm::dvec4 htex_lookup(const std::vector<HalfedgeMesh>& meshes, const htex::AtlasLayout& layout, const HtexTexture& texture,
                       uint32_t mesh, uint32_t face, const glm::dvec3& bary, uint32_t level);

}  // namespace prismoid::reference
