#include "renderer/reference/htex_reference.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace prismoid::reference {

namespace {

// Bilinear taps along one axis for a side of n texels: texel i0 with weight 1 - f and i0 + 1
// with weight f, where texel i sits at (i + 0.5) / n. Taps outside [0, n) read the zero border.
struct Taps {
  int64_t i0;
  double f;
};
Taps taps(double t, uint32_t n) {
  const double s = t * n - 0.5;
  const double i0 = std::floor(s);
  return {static_cast<int64_t>(i0), s - i0};
}

}  // namespace

HtexFootprint htex_footprint(const std::vector<HalfedgeMesh>& meshes, const htex::AtlasLayout& layout, uint32_t mesh,
                             uint32_t face, const glm::dvec3& bary, uint32_t level) {
  const htex::MeshLayout& m = layout.meshes().at(mesh);
  if (level >= m.levels) throw std::out_of_range("htex: level " + std::to_string(level) + " is past the mesh's mip chain");
  const uint32_t n = m.side(level);
  HtexFootprint fp;
  for (const htex::QuadPoint& q : htex::face_point_quads(meshes.at(mesh), face, bary)) {
    const Taps x = taps(q.xy.x, n), y = taps(q.xy.y, n);
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const int64_t i = x.i0 + dx, j = y.i0 + dy;
        const double w = (dx ? x.f : 1.0 - x.f) * (dy ? y.f : 1.0 - y.f);
        if (i < 0 || j < 0 || i >= n || j >= n || w <= 0.0) continue;  // border: colour and alpha 0
        fp.texels[fp.count++] = {{m.first_quad + q.edge, level, static_cast<uint32_t>(i), static_cast<uint32_t>(j)}, w};
        fp.alpha += w;
      }
  }
  for (uint32_t k = 0; k < fp.count; ++k) fp.texels[k].weight /= fp.alpha;
  return fp;
}

double htex_level_of_detail(const htex::MeshLayout& layout, uint32_t face, const glm::dvec3& bary, const glm::dvec3& dbary_dx,
                            const glm::dvec3& dbary_dy) {
  const htex::HalfedgePoint p = htex::locate_in_face(face, bary);
  const int k = HalfedgeMesh::corner(p.halfedge), m = (k + 2) % 3;
  auto local = [&](const glm::dvec3& d) { return glm::dvec2(d[k] - d[m], d[(k + 1) % 3] - d[m]); };
  const double scale = std::max(glm::length(local(dbary_dx)), glm::length(local(dbary_dy))) * layout.side(0);
  return std::log2(scale);
}

std::vector<uint32_t> htex_footprint_shadels(const htex::AtlasLayout& layout, const HtexFootprint& footprint) {
  std::vector<uint32_t> shadels;
  for (uint32_t k = 0; k < footprint.count; ++k) shadels.push_back(layout.shadel_of(layout.virtual_texel(footprint.texels[k].texel)));
  std::sort(shadels.begin(), shadels.end());
  shadels.erase(std::unique(shadels.begin(), shadels.end()), shadels.end());
  return shadels;
}

HtexTexture::HtexTexture(const htex::AtlasLayout& layout, uint32_t channels) : layout_(&layout), channels_(channels) {
  if (channels < 1 || channels > 4) throw std::invalid_argument("htex: a texture has 1 to 4 channels");
  size_t total = 0;
  for (const htex::MeshLayout& m : layout.meshes()) {
    auto& bases = base_.emplace_back();
    for (uint32_t level = 0; level < m.levels; ++level) {
      bases.push_back(total);
      total += size_t(m.quad_count) * m.side(level) * m.side(level) * channels;
    }
  }
  values_.assign(total, 0.0);
}

size_t HtexTexture::offset(const htex::TexelAddress& t) const {
  const uint32_t mesh = layout_->mesh_of_quad(t.quad);
  const htex::MeshLayout& m = layout_->meshes()[mesh];
  if (t.level >= m.levels) throw std::out_of_range("htex: level past the quad's mip chain");
  const size_t n = m.side(t.level);
  if (t.i >= n || t.j >= n) throw std::out_of_range("htex: texel outside its quad");
  return base_[mesh][t.level] + ((size_t(t.quad - m.first_quad) * n + t.j) * n + t.i) * channels_;
}

glm::dvec4 HtexTexture::get(const htex::TexelAddress& t) const {
  const size_t o = offset(t);
  glm::dvec4 v(0.0);
  for (uint32_t c = 0; c < channels_; ++c) v[c] = values_[o + c];
  return v;
}

void HtexTexture::set(const htex::TexelAddress& t, const glm::dvec4& value) {
  const size_t o = offset(t);
  for (uint32_t c = 0; c < channels_; ++c) values_[o + c] = value[c];
}

void htex_shade_all(const std::vector<HalfedgeMesh>& meshes, const htex::AtlasLayout& layout, const HtexShader& shade,
                    HtexTexture& texture, bool snap_vertex_corners) {
  for (uint32_t mesh = 0; mesh < meshes.size(); ++mesh) {
    const htex::MeshLayout& m = layout.meshes().at(mesh);
    for (uint32_t level = 0; level < m.levels; ++level) {
      const uint32_t n = m.side(level);
      for (uint32_t e = 0; e < m.quad_count; ++e)
        for (uint32_t j = 0; j < n; ++j)
          for (uint32_t i = 0; i < n; ++i)
            texture.set({m.first_quad + e, level, i, j},
                        shade(mesh, htex::texel_point(meshes[mesh], e, n, i, j, snap_vertex_corners)));
    }
  }
}

glm::dvec4 htex_lookup(const std::vector<HalfedgeMesh>& meshes, const htex::AtlasLayout& layout, const HtexTexture& texture,
                       uint32_t mesh, uint32_t face, const glm::dvec3& bary, uint32_t level) {
  const HtexFootprint fp = htex_footprint(meshes, layout, mesh, face, bary, level);
  glm::dvec4 value(0.0);
  for (uint32_t k = 0; k < fp.count; ++k) value += fp.texels[k].weight * texture.get(fp.texels[k].texel);
  return value;
}

}  // namespace prismoid::reference
