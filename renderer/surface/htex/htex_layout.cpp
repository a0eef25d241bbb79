#include "renderer/surface/htex/htex_layout.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace prismoid::htex {

namespace {

uint32_t round_up(uint32_t value, uint32_t multiple) { return (value + multiple - 1) / multiple * multiple; }

// Largest singular value of the 3x2 map [a b].
double stretch(const glm::dvec3& a, const glm::dvec3& b) {
  const double aa = glm::dot(a, a), bb = glm::dot(b, b), ab = glm::dot(a, b);
  const double half_trace = 0.5 * (aa + bb);
  const double det = std::max(aa * bb - ab * ab, 0.0);
  return std::sqrt(half_trace + std::sqrt(std::max(half_trace * half_trace - det, 0.0)));
}

}  // namespace

// ---- Charts -----------------------------------------------------------------------------------

HalfedgePoint locate_in_face(uint32_t face, const glm::dvec3& bary) {
  // In halfedge triangle k (from p_k to p_(k+1)) with m = k + 2: the centroid carries
  // w / 3 of every weight, so b_m = w / 3, b_k = w / 3 + u, b_(k+1) = w / 3 + v. The point lies
  // in the halfedge triangle whose m has the smallest weight.
  int m = 0;
  if (bary[1] < bary[m]) m = 1;
  if (bary[2] < bary[m]) m = 2;
  const int k = (m + 1) % 3;
  return {static_cast<int32_t>(3 * face + k), {bary[k] - bary[m], bary[(k + 1) % 3] - bary[m]}};
}

glm::dvec3 face_barycentric(int32_t halfedge, const glm::dvec2& uv) {
  const int k = HalfedgeMesh::corner(halfedge);
  const double third = (1.0 - uv.x - uv.y) / 3.0;
  glm::dvec3 b(third);
  b[k] += uv.x;
  b[(k + 1) % 3] += uv.y;
  return b;
}

glm::dvec2 quad_coordinates(const HalfedgeMesh& mesh, int32_t halfedge, const glm::dvec2& uv) {
  return mesh.primary(halfedge) ? uv : glm::dvec2(1.0) - uv;
}

std::array<QuadPoint, 3> face_point_quads(const HalfedgeMesh& mesh, uint32_t face, const glm::dvec3& bary) {
  const HalfedgePoint p = locate_in_face(face, bary);
  const int32_t h = p.halfedge, n = HalfedgeMesh::next(h), q = HalfedgeMesh::prev(h);
  const double u = p.uv.x, v = p.uv.y;
  return {{{mesh.edge_of[h], quad_coordinates(mesh, h, {u, v})},
           {mesh.edge_of[n], quad_coordinates(mesh, n, {v, -u})},
           {mesh.edge_of[q], quad_coordinates(mesh, q, {-v, u})}}};
}

QuadSurfacePoint quad_surface_point(const HalfedgeMesh& mesh, uint32_t edge, const glm::dvec2& xy) {
  const int32_t p = mesh.edge_halfedge[edge];
  const int32_t t = mesh.twin[p];
  if (xy.x + xy.y <= 1.0 || t == kNoHalfedge) {
    return {static_cast<uint32_t>(HalfedgeMesh::face(p)), face_barycentric(p, xy), xy.x + xy.y > 1.0};
  }
  return {static_cast<uint32_t>(HalfedgeMesh::face(t)), face_barycentric(t, glm::dvec2(1.0) - xy), false};
}

TexelPoint texel_point(const HalfedgeMesh& mesh, uint32_t edge, uint32_t n, uint32_t i, uint32_t j, bool snap_vertex_corners) {
  TexelPoint texel;
  const int32_t p = mesh.edge_halfedge[edge];
  if (snap_vertex_corners && n >= 2 && ((i == n - 1 && j == 0) || (i == 0 && j == n - 1))) {
    // start(p) at (1, 0), end(p) at (0, 1); shaded in the vertex's own corner (vertex_halfedge),
    // the same triangle for every quad around the vertex, so that shading terms that depend on
    // the triangle (its geometric normal, its emitter) agree there too.
    const int32_t from = i == n - 1 ? p : HalfedgeMesh::next(p);
    const int32_t c = canonical_corner(mesh, from);
    texel.face = static_cast<uint32_t>(HalfedgeMesh::face(c));
    texel.bary = glm::dvec3(0.0);
    texel.bary[HalfedgeMesh::corner(c)] = 1.0;
    texel.vertex = static_cast<int32_t>(mesh.vertex(c));
    texel.position = mesh.positions[texel.vertex];
    return texel;
  }
  const glm::dvec2 xy((i + 0.5) / n, (j + 0.5) / n);
  const QuadSurfacePoint s = quad_surface_point(mesh, edge, xy);
  texel.face = s.face;
  texel.bary = s.bary;
  texel.ghost = s.ghost;
  const auto& f = mesh.faces[s.face];
  texel.position = s.bary[0] * mesh.positions[f[0]] + s.bary[1] * mesh.positions[f[1]] + s.bary[2] * mesh.positions[f[2]];
  return texel;
}

int32_t canonical_corner(const HalfedgeMesh& mesh, int32_t h) {
  const int32_t c = mesh.vertex_halfedge[mesh.vertex(h)];
  return c == kNoHalfedge ? h : c;
}

double quad_stretch(const HalfedgeMesh& mesh, uint32_t edge) {
  double s = 0.0;
  for (int32_t h : {mesh.edge_halfedge[edge], mesh.twin[mesh.edge_halfedge[edge]]}) {
    if (h == kNoHalfedge) continue;
    const glm::dvec3 c = face_center(mesh, static_cast<uint32_t>(HalfedgeMesh::face(h)));
    s = std::max(s, stretch(mesh.positions[mesh.vertex(h)] - c, mesh.positions[mesh.target(h)] - c));
  }
  return s;
}

// ---- Atlas ------------------------------------------------------------------------------------

glm::uvec2 MeshLayout::extent(uint32_t level) const {
  return {round_up(columns * side(level), kShadelTexels), round_up(rows * side(level), kShadelTexels)};
}

AtlasLayout::AtlasLayout(const std::vector<HalfedgeMesh>& meshes, const LayoutOptions& options) {
  const uint32_t min_log2 = std::max(options.min_log2, 1u);
  const uint32_t max_log2 = std::max(options.max_log2, min_log2);
  if (max_log2 > 15) throw std::invalid_argument("htex: quad sides above 2^15 texels are not addressable");
  if (!(options.texels_per_unit > 0.0) || !std::isfinite(options.texels_per_unit))
    throw std::invalid_argument("htex: texels_per_unit must be positive and finite");

  // Per mesh: quad side from the largest quad, scan-line grid of quads.
  uint64_t quads = 0;
  for (const HalfedgeMesh& mesh : meshes) {
    MeshLayout m;
    m.first_quad = static_cast<uint32_t>(quads);
    m.quad_count = static_cast<uint32_t>(mesh.edge_count());
    quads += m.quad_count;
    for (uint32_t e = 0; e < m.quad_count; ++e) m.largest_stretch = std::max(m.largest_stretch, quad_stretch(mesh, e));
    const double wanted = m.largest_stretch * options.texels_per_unit;  // texels across the largest quad
    const double log2_wanted = wanted > 1.0 ? std::ceil(std::log2(wanted) - 1e-9) : 0.0;
    m.log2_side = static_cast<uint32_t>(std::clamp(log2_wanted, double(min_log2), double(max_log2)));
    m.levels = m.log2_side;  // sides 2^log2_side down to 2
    m.columns = std::max(1u, static_cast<uint32_t>(std::ceil(std::sqrt(double(m.quad_count)))));
    m.rows = std::max(1u, (m.quad_count + m.columns - 1) / m.columns);
    m.origin.assign(m.levels, glm::uvec2(0));
    meshes_.push_back(std::move(m));
  }
  if (quads > UINT32_MAX) throw std::invalid_argument("htex: more than 2^32 quads");
  quad_count_ = static_cast<uint32_t>(quads);

  // Shelf packing of every (mesh, level) rectangle, tallest first.
  struct Rect {
    uint32_t mesh, level;
    glm::uvec2 size;
  };
  std::vector<Rect> rects;
  uint64_t area = 0;
  uint32_t widest = kGroupTexels;
  for (uint32_t m = 0; m < meshes_.size(); ++m) {
    if (meshes_[m].quad_count == 0) continue;
    for (uint32_t level = 0; level < meshes_[m].levels; ++level) {
      const glm::uvec2 size = meshes_[m].extent(level);
      rects.push_back({m, level, size});
      area += uint64_t(size.x) * size.y;
      widest = std::max(widest, size.x);
    }
  }
  std::stable_sort(rects.begin(), rects.end(), [](const Rect& a, const Rect& b) {
    return a.size.y != b.size.y ? a.size.y > b.size.y : a.size.x > b.size.x;
  });
  uint64_t width = kGroupTexels;
  while (width < widest || width * width < area) width *= 2;
  if (width > (1u << 30)) throw std::invalid_argument("htex: the virtual atlas would be wider than 2^30 texels");
  width_ = static_cast<uint32_t>(width);
  uint64_t shelf_y = 0, shelf_height = 0, x = 0;
  for (const Rect& r : rects) {
    if (x + r.size.x > width_) {
      shelf_y += shelf_height;
      shelf_height = 0;
      x = 0;
    }
    if (shelf_y + r.size.y > (1u << 30)) throw std::invalid_argument("htex: the virtual atlas would be taller than 2^30 texels");
    meshes_[r.mesh].origin[r.level] = glm::uvec2(static_cast<uint32_t>(x), static_cast<uint32_t>(shelf_y));
    x += r.size.x;
    shelf_height = std::max<uint64_t>(shelf_height, r.size.y);
  }
  height_ = std::max(kGroupTexels, round_up(static_cast<uint32_t>(shelf_y + shelf_height), kGroupTexels));

  // Shadel -> region table.
  shadel_region_.assign(size_t(shadel_columns()) * shadel_rows(), -1);
  for (const Rect& r : rects) {
    const auto id = static_cast<int32_t>(regions_.size());
    regions_.push_back({r.mesh, r.level});
    const glm::uvec2 o = meshes_[r.mesh].origin[r.level] / kShadelTexels;
    for (uint32_t sy = 0; sy < r.size.y / kShadelTexels; ++sy)
      for (uint32_t sx = 0; sx < r.size.x / kShadelTexels; ++sx)
        shadel_region_[size_t(o.y + sy) * shadel_columns() + o.x + sx] = id;
  }
}

uint32_t AtlasLayout::mesh_of_quad(uint32_t quad) const {
  if (quad >= quad_count_) throw std::out_of_range("htex: quad " + std::to_string(quad) + " is not in the atlas");
  const auto it = std::upper_bound(meshes_.begin(), meshes_.end(), quad,
                                   [](uint32_t q, const MeshLayout& m) { return q < m.first_quad; });
  // The last mesh starting at or before `quad` that has quads (empty meshes share first_quad).
  auto m = static_cast<uint32_t>(it - meshes_.begin()) - 1;
  while (meshes_[m].quad_count == 0 || quad >= meshes_[m].first_quad + meshes_[m].quad_count) --m;
  return m;
}

glm::uvec2 AtlasLayout::virtual_texel(const TexelAddress& t) const {
  const MeshLayout& m = meshes_[mesh_of_quad(t.quad)];
  if (t.level >= m.levels) throw std::out_of_range("htex: level " + std::to_string(t.level) + " is past the quad's mip chain");
  const uint32_t n = m.side(t.level);
  if (t.i >= n || t.j >= n) throw std::out_of_range("htex: texel outside its quad");
  const uint32_t local = t.quad - m.first_quad;
  return m.origin[t.level] + glm::uvec2((local % m.columns) * n + t.i, (local / m.columns) * n + t.j);
}

std::optional<TexelAddress> AtlasLayout::texel_at(const glm::uvec2& v) const {
  if (v.x >= width_ || v.y >= height_) return std::nullopt;
  const auto region = region_of_shadel(shadel_of(v));
  if (!region) return std::nullopt;
  const MeshLayout& m = meshes_[region->mesh];
  const uint32_t n = m.side(region->level);
  const glm::uvec2 d = v - m.origin[region->level];
  const uint32_t column = d.x / n, row = d.y / n;
  if (column >= m.columns || row >= m.rows) return std::nullopt;
  const uint32_t local = row * m.columns + column;
  if (local >= m.quad_count) return std::nullopt;
  return TexelAddress{m.first_quad + local, region->level, d.x % n, d.y % n};
}

std::optional<AtlasLayout::Region> AtlasLayout::region_of_shadel(uint32_t shadel) const {
  if (shadel >= shadel_region_.size() || shadel_region_[shadel] < 0) return std::nullopt;
  return regions_[shadel_region_[shadel]];
}

}  // namespace prismoid::htex
