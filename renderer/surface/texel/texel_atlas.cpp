#include "renderer/surface/texel/texel_atlas.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "renderer/surface/charts/planar_charts.hpp"
#include "scene/input_error.hpp"

namespace prismoid::texel {

namespace {

constexpr double kSqrt2 = 1.4142135623730951;

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }
double orient(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& p) { return cross2(b - a, p - a); }

uint64_t round_up(uint64_t value, uint64_t multiple) { return (value + multiple - 1) / multiple * multiple; }

double longest_edge_sq(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
}

// Twice the signed area of the uv triangle, or 0 when it is degenerate (the 3D rule,
// charts::kDegenerateTriangle): such a triangle gets the centroid's weights.
double usable_area2(const std::array<glm::dvec2, 3>& t) {
  const double a2 = orient(t[0], t[1], t[2]);
  if (!std::isfinite(a2) || std::abs(a2) <= charts::kDegenerateTriangle * longest_edge_sq(t[0], t[1], t[2])) return 0.0;
  return a2;
}

struct Size64 {
  uint64_t x = 0, y = 0;
};

struct Box2 {
  glm::dvec2 lo, hi;
};

Box2 box_of(const std::array<glm::dvec2, 3>& t) {
  return {glm::min(t[0], glm::min(t[1], t[2])), glm::max(t[0], glm::max(t[1], t[2]))};
}

// Squared distance from p to segment [a, b].
double segment_distance_sq(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b) {
  const glm::dvec2 ab = b - a, ap = p - a;
  const double len2 = glm::dot(ab, ab);
  double s = len2 > 0.0 ? glm::dot(ap, ab) / len2 : 0.0;
  s = std::clamp(s, 0.0, 1.0);
  const glm::dvec2 d = ap - s * ab;
  return glm::dot(d, d);
}

// A point within this distance (texels) of a triangle counts as on it: a centre on an edge two
// triangles share is then on both whatever the rounding, and the lower id keeps it.
constexpr double kOnTriangle = 1e-9;

// Squared distance from p to the closed triangle t (0 inside or within kOnTriangle);
// `area2` = usable_area2(t).
double triangle_distance_sq(const glm::dvec2& p, const std::array<glm::dvec2, 3>& t, double area2) {
  if (area2 > 0.0 && orient(t[0], t[1], p) >= 0.0 && orient(t[1], t[2], p) >= 0.0 && orient(t[2], t[0], p) >= 0.0) return 0.0;
  const double d2 = std::min({segment_distance_sq(p, t[0], t[1]), segment_distance_sq(p, t[1], t[2]), segment_distance_sq(p, t[2], t[0])});
  return d2 <= kOnTriangle * kOnTriangle ? 0.0 : d2;
}

// triangle_distance_sq's rule, prepared for many points and cut off beyond sqrt(2): the squared
// distance when it is <= 2, else something > 2.
class TriangleDistance {
 public:
  explicit TriangleDistance(const std::array<glm::dvec2, 3>& t) : t_(t), area2_(usable_area2(t)) {
    for (int k = 0; k < 3; ++k) {
      const double len = glm::length(t[(k + 1) % 3] - t[k]);
      inv_len_[k] = len > 0.0 ? 1.0 / len : 0.0;
    }
  }
  double operator()(const glm::dvec2& p) const {
    if (!(area2_ > 0.0)) return triangle_distance_sq(p, t_, area2_);
    double s[3];
    for (int k = 0; k < 3; ++k) s[k] = orient(t_[k], t_[(k + 1) % 3], p);
    if (s[0] >= 0.0 && s[1] >= 0.0 && s[2] >= 0.0) return 0.0;
    // Beyond sqrt(2) of an edge's line (on its outer side): beyond sqrt(2) of the triangle.
    for (int k = 0; k < 3; ++k)
      if (s[k] * inv_len_[k] < -kSqrt2 * (1.0 + 1e-12)) return 4.0;
    // The nearest point lies on an edge that has p on its outer side.
    double d2 = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k)
      if (s[k] < 0.0) d2 = std::min(d2, segment_distance_sq(p, t_[k], t_[(k + 1) % 3]));
    return d2 <= kOnTriangle * kOnTriangle ? 0.0 : d2;
  }

 private:
  std::array<glm::dvec2, 3> t_;
  double area2_;
  double inv_len_[3];
};

// Andrew's monotone chain: counter-clockwise hull without collinear points.
std::string fmt(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace

// ---- Offsets and counts -------------------------------------------------------------------------

uint64_t TexelAtlas::texel_offset(uint32_t level) const {
  uint64_t offset = 0;
  for (uint32_t l = 0; l < level; ++l) offset += uint64_t(level_width(l)) * level_height(l);
  return offset;
}

uint64_t TexelAtlas::tile_offset(uint32_t level) const {
  uint64_t offset = 0;
  for (uint32_t l = 0; l < level; ++l) offset += uint64_t(level_width(l) / kTileTexels) * (level_height(l) / kTileTexels);
  return offset;
}

uint64_t TexelAtlas::used_texels() const {
  uint64_t used = 0;
  for (const auto& level : triangle_index)
    used += static_cast<uint64_t>(std::count_if(level.begin(), level.end(), [](uint32_t t) { return t != kNoTriangle; }));
  return used;
}

uint64_t TexelAtlas::covered_texels_level0() const {
  if (triangle_index.empty()) return 0;
  uint64_t covered = 0;
  for (uint32_t j = 0; j < height; ++j) {
    for (uint32_t i = 0; i < width; ++i) {
      const uint32_t t = triangle_at(0, i, j);
      if (t == kNoTriangle) continue;
      // The texel holds a triangle containing its centre whenever one does.
      const double area2 = usable_area2(corner_uv[t]);
      if (area2 > 0.0 && triangle_distance_sq({i + 0.5, j + 0.5}, corner_uv[t], area2) == 0.0) ++covered;
    }
  }
  return covered;
}

// ---- Building ---------------------------------------------------------------------------------

TexelAtlas build_texel_atlas(const SurfaceScene& scene, const AtlasSettings& settings) {
  const std::string& name = scene.name;
  if (settings.levels < 1 || settings.levels > kMaxLevels)
    throw InputError(name, "texel atlas: levels must be 1.." + std::to_string(kMaxLevels) + ", not " + std::to_string(settings.levels));
  if (!(settings.max_normal_angle_deg > 0.0 && settings.max_normal_angle_deg < 90.0))
    throw InputError(name, "texel atlas: the charts' normal angle must lie in (0, 90) degrees, not " + fmt(settings.max_normal_angle_deg));
  if (settings.max_chart_triangles == 0) throw InputError(name, "texel atlas: a chart must be allowed at least one triangle");
  if (!(settings.target_texels > 0.0) || !std::isfinite(settings.target_texels))
    throw InputError(name, "texel atlas: the target texel count must be positive and finite, not " + fmt(settings.target_texels));
  if (!(settings.texels_per_unit >= 0.0) || !std::isfinite(settings.texels_per_unit))
    throw InputError(name, "texel atlas: texels per unit must be finite and >= 0 (0: from the target), not " + fmt(settings.texels_per_unit));

  const uint32_t levels = settings.levels;
  const uint64_t align = uint64_t(1) << (levels - 1);  // level-0 texels of one coarsest-level texel
  const uint64_t padding = padding_texels(levels);
  const uint64_t side_align = kTileTexels * align;

  // Charts (planar_charts.hpp): grown over shared edges, turned to their minimum-area rectangle.
  const std::vector<charts::TriangleGeometry> tris = charts::triangle_geometry(scene);
  const uint32_t triangle_count = static_cast<uint32_t>(tris.size());
  double total_area = 0.0;
  for (const auto& g : tris) total_area += g.area;  // 0 for degenerate triangles

  double rho = settings.texels_per_unit;
  if (rho == 0.0) rho = total_area > 0.0 ? std::sqrt(settings.target_texels / total_area) : 1.0;
  if (!(rho > 0.0) || !std::isfinite(rho)) throw InputError(name, "texel atlas: no usable texel density (" + fmt(rho) + " texels per unit)");

  std::vector<charts::PlanarChart> planar = charts::grow_planar_charts(scene, tris, settings.max_chart_triangles, settings.max_normal_angle_deg);

  // Chart-local uv: level-0 texels, the rectangle's lower corner at 0.
  TexelAtlas atlas;
  atlas.levels = levels;
  atlas.texels_per_unit = rho;
  atlas.chart_of_triangle.assign(triangle_count, kNoTriangle);
  atlas.corner_uv.assign(triangle_count, {});
  atlas.charts.resize(planar.size());
  std::vector<std::array<glm::dvec2, 3>> local_uv(triangle_count);
  for (size_t c = 0; c < planar.size(); ++c) {
    const charts::PlanarChart& chart = planar[c];
    for (size_t k = 0; k < chart.triangles.size(); ++k) {
      const uint32_t t = chart.triangles[k];
      atlas.chart_of_triangle[t] = static_cast<uint32_t>(c);
      for (int v = 0; v < 3; ++v) local_uv[t][v] = chart.corners[k][v] * rho;
    }
  }

  // ---- Packing: shelves, tallest first ----
  const auto too_large = [&](const std::string& what) {
    return InputError(name, "texel atlas: " + what + " exceeds the largest side of " + std::to_string(settings.max_side) +
                                " texels at " + fmt(rho) + " texels per unit; use a lower texel density");
  };
  std::vector<Size64> padded(planar.size());
  uint64_t widest = 0;
  double total_padded = 0.0;
  for (size_t c = 0; c < planar.size(); ++c) {
    const glm::dvec2 content = planar[c].extent * rho;
    if (!(content.x <= double(settings.max_side)) || !(content.y <= double(settings.max_side))) throw too_large("a chart");
    const uint64_t cw = std::max<uint64_t>(align, round_up(static_cast<uint64_t>(std::ceil(content.x)), align));
    const uint64_t ch = std::max<uint64_t>(align, round_up(static_cast<uint64_t>(std::ceil(content.y)), align));
    padded[c] = {cw + 2 * padding, ch + 2 * padding};
    widest = std::max(widest, padded[c].x);
    total_padded += double(padded[c].x) * double(padded[c].y);
  }
  if (widest > settings.max_side) throw too_large("a chart");
  const uint64_t width = std::max({side_align, round_up(static_cast<uint64_t>(std::ceil(std::sqrt(total_padded))), side_align), round_up(widest, side_align)});
  if (width > settings.max_side || width > std::numeric_limits<uint32_t>::max()) throw too_large("the atlas's width");
  std::vector<uint32_t> order(planar.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (padded[a].y != padded[b].y) return padded[a].y > padded[b].y;
    if (padded[a].x != padded[b].x) return padded[a].x > padded[b].x;
    return a < b;
  });
  std::vector<Size64> origin(planar.size());
  uint64_t x = 0, shelf_y = 0, shelf_h = 0;
  for (uint32_t c : order) {
    if (x + padded[c].x > width) {
      shelf_y += shelf_h;
      x = 0;
      shelf_h = 0;
    }
    origin[c] = {x, shelf_y};
    x += padded[c].x;
    shelf_h = std::max(shelf_h, padded[c].y);
    if (shelf_y + shelf_h > settings.max_side) throw too_large("the atlas's height");
  }
  const uint64_t height = std::max(side_align, round_up(shelf_y + shelf_h, side_align));
  if (height > settings.max_side || height > std::numeric_limits<uint32_t>::max()) throw too_large("the atlas's height");
  atlas.width = static_cast<uint32_t>(width);
  atlas.height = static_cast<uint32_t>(height);

  for (size_t c = 0; c < planar.size(); ++c) {
    Chart& out = atlas.charts[c];
    out.mesh = planar[c].mesh;
    out.triangles = std::move(planar[c].triangles);
    out.origin = glm::uvec2(static_cast<uint32_t>(origin[c].x), static_cast<uint32_t>(origin[c].y));
    out.size = glm::uvec2(static_cast<uint32_t>(padded[c].x), static_cast<uint32_t>(padded[c].y));
    const glm::dvec2 content_origin(double(origin[c].x + padding), double(origin[c].y + padding));
    for (uint32_t t : out.triangles) {
      for (int v = 0; v < 3; ++v) atlas.corner_uv[t][v] = content_origin + local_uv[t][v];  // point-like: all at the origin
    }
  }

  // ---- Triangle index textures ----
  atlas.triangle_index.resize(levels);
  std::vector<float> best;
  for (uint32_t level = 0; level < levels; ++level) {
    const uint32_t w = atlas.level_width(level), h = atlas.level_height(level);
    auto& index = atlas.triangle_index[level];
    index.assign(uint64_t(w) * h, kNoTriangle);
    best.assign(index.size(), std::numeric_limits<float>::infinity());
    const double scale = 1.0 / double(1u << level);
    for (const Chart& chart : atlas.charts) {
      const int64_t ci0 = chart.origin.x >> level, cj0 = chart.origin.y >> level;
      const int64_t ci1 = int64_t(chart.origin.x + chart.size.x) >> level, cj1 = int64_t(chart.origin.y + chart.size.y) >> level;  // exclusive
      for (uint32_t t : chart.triangles) {  // ascending ids: an equal distance keeps the lower id
        std::array<glm::dvec2, 3> q;
        for (int v = 0; v < 3; ++v) q[v] = atlas.corner_uv[t][v] * scale;
        const TriangleDistance distance_sq(q);
        const Box2 box = box_of(q);
        // Texel centres i + 0.5 within sqrt(2) of the box.
        const int64_t i0 = std::max(ci0, static_cast<int64_t>(std::ceil(box.lo.x - kSqrt2 - 0.5)));
        const int64_t i1 = std::min(ci1 - 1, static_cast<int64_t>(std::floor(box.hi.x + kSqrt2 - 0.5)));
        const int64_t j0 = std::max(cj0, static_cast<int64_t>(std::ceil(box.lo.y - kSqrt2 - 0.5)));
        const int64_t j1 = std::min(cj1 - 1, static_cast<int64_t>(std::floor(box.hi.y + kSqrt2 - 0.5)));
        for (int64_t j = j0; j <= j1; ++j) {
          for (int64_t i = i0; i <= i1; ++i) {
            const double d2 = distance_sq({double(i) + 0.5, double(j) + 0.5});
            if (!(d2 <= 2.0)) continue;
            const uint64_t at = uint64_t(j) * w + uint64_t(i);
            const float d2f = static_cast<float>(d2);
            if (d2f < best[at]) {
              best[at] = d2f;
              index[at] = t;
            }
          }
        }
      }
    }
  }
  return atlas;
}

// ---- Lookup -----------------------------------------------------------------------------------

glm::dvec2 atlas_uv(const TexelAtlas& atlas, uint32_t triangle, const glm::dvec3& bary) {
  const auto& c = atlas.corner_uv[triangle];
  return bary[0] * c[0] + bary[1] * c[1] + bary[2] * c[2];
}

glm::dvec3 texel_barycentric(const TexelAtlas& atlas, uint32_t triangle, uint32_t level, uint32_t i, uint32_t j) {
  const auto& c = atlas.corner_uv[triangle];
  const double size = double(1u << level);
  const glm::dvec2 p((double(i) + 0.5) * size, (double(j) + 0.5) * size);
  const double area2 = usable_area2(c);
  if (area2 == 0.0) return glm::dvec3(1.0 / 3.0);
  const double b1 = cross2(p - c[0], c[2] - c[0]) / area2;
  const double b2 = cross2(c[1] - c[0], p - c[0]) / area2;
  return {1.0 - b1 - b2, b1, b2};
}

uint32_t select_level(double footprint, double bias, uint32_t levels) {
  if (levels <= 1 || !(footprint > 0.0) || !std::isfinite(footprint)) return 0;
  const double level = std::floor(std::log2(footprint) + bias);
  if (std::isnan(level) || level <= 0.0) return 0;
  if (level >= double(levels - 1)) return levels - 1;
  return static_cast<uint32_t>(level);
}

std::array<Tap, 4> bilinear_taps(const TexelAtlas& atlas, const glm::dvec2& uv, uint32_t level) {
  std::array<Tap, 4> taps{};
  const glm::dvec2 t = uv / double(1u << level) - 0.5;
  if (!std::isfinite(t.x) || !std::isfinite(t.y)) return taps;  // texel (0, 0), weight 0
  const glm::dvec2 base = glm::floor(t);
  const glm::dvec2 f = t - base;
  const double w_max = double(atlas.level_width(level)) - 1.0, h_max = double(atlas.level_height(level)) - 1.0;
  // Order: (i0, j0), (i0 + 1, j0), (i0, j0 + 1), (i0 + 1, j0 + 1).
  const double weights[4] = {(1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y};
  double sum = 0.0;
  for (int k = 0; k < 4; ++k) {
    const double i = std::clamp(base.x + double(k & 1), 0.0, std::max(w_max, 0.0));
    const double j = std::clamp(base.y + double(k >> 1), 0.0, std::max(h_max, 0.0));
    taps[k].texel = glm::uvec2(static_cast<uint32_t>(i), static_cast<uint32_t>(j));
    const bool has = !atlas.triangle_index.empty() && atlas.level_width(level) > 0 && atlas.level_height(level) > 0 &&
                     atlas.triangle_at(level, taps[k].texel.x, taps[k].texel.y) != kNoTriangle;
    taps[k].weight = has ? weights[k] : 0.0;
    sum += taps[k].weight;
  }
  if (sum > 0.0)
    for (auto& tap : taps) tap.weight /= sum;
  else
    for (auto& tap : taps) tap.weight = 0.0;
  return taps;
}

}  // namespace prismoid::texel
