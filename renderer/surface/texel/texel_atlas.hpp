#pragma once
// The static texture atlas of the texel shading backend (Hillesland & Yang 2016, "Texel
// Shading"): plain data and math, no Vulkan. Texel shading needs a unique,
// static parametrization of every surface; surface files rarely carry one, so this builds it:
//
// Charts. Triangles are grown into charts over shared edges (a triangle joins a chart when its
// normal is within `max_normal_angle_deg` of the chart's seed normal and its projection onto the
// chart's plane neither flips nor overlaps a triangle already in the chart), up to
// `max_chart_triangles`. A chart is the orthogonal projection of its triangles onto the plane
// through the seed with the seed's normal, turned so that its convex hull's minimum-area
// bounding rectangle is axis-aligned (rotating calipers), scaled by `texels_per_unit`. The map is
// affine on each triangle and injective on the chart, so every point of the surface has exactly
// one atlas position. Degenerate triangles (zero area) form charts of their own with a point-like
// map; nothing ever samples them (the rasterizer covers no pixel of them).
//
// Levels. Level L halves level L - 1 (`levels` levels, 0 finest). Atlas coordinates ("uv") are
// in level-0 texel units: texel (i, j) of level L covers [i, i + 1) x [j, j + 1) times 2^L and
// its centre is ((i + 0.5) 2^L, (j + 0.5) 2^L).
//
// Packing. Each chart's rectangle is placed on a grid of 2^(levels - 1) level-0 texels with
// kPaddingTexels(levels) = 2^levels texels of padding on every side, so at every level a texel
// belongs to one chart's padded rectangle and at least 2 texels of padding surround its content
// (what bilinear taps reach, below). Shelf packing, tallest first. The atlas's sides are
// multiples of 8 * 2^(levels - 1), so every level tiles into whole 8 x 8 tiles.
//
// Triangle index texture (the paper's, one per level). Texel (i, j) of level L holds the
// triangle of its chart that contains its centre (the lowest id on a shared edge), else the
// chart's triangle nearest to its centre when that is within sqrt(2) texels of level L (the
// bilinear taps of any point inside a triangle lie within that distance), else kNoTriangle.
// A texel's shading point is its centre mapped back through its triangle's affine map: inside
// the triangle, or in the triangle's plane just beyond an edge for padding texels.
//
// Lookup (the gather and the shade queue, GPU and CPU alike). A pixel's point has atlas
// coordinates uv (its triangle's corner uvs blended by its barycentric weights). Its level is
// floor(log2(footprint) + bias) clamped to [0, levels - 1], footprint = the longer of the uv
// changes one pixel right and one pixel down (rounding down picks the finer level, as the paper
// does). Its four bilinear taps at level L are the texels around uv / 2^L - 0.5; a tap whose
// texel holds kNoTriangle gets weight 0 and the others are renormalized.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/surface_scene.hpp"

namespace prismoid::texel {

inline constexpr uint32_t kTileTexels = 8;  // the paper's 8 x 8 shading tiles
inline constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;
inline constexpr uint32_t kMaxLevels = 8;
inline constexpr uint32_t kPaddingTexelsPerLevelUnit = 2;  // padding = 2 texels of the coarsest level
inline constexpr uint32_t padding_texels(uint32_t levels) { return kPaddingTexelsPerLevelUnit << (levels - 1); }

struct AtlasSettings {
  // Level-0 texels per world unit. 0: chosen so that the charts' triangles cover about
  // `target_texels` level-0 texels in all.
  double texels_per_unit = 0.0;
  double target_texels = double(1u << 22);
  uint32_t levels = 4;                  // 1 .. kMaxLevels
  uint32_t max_chart_triangles = 512;
  double max_normal_angle_deg = 60.0;   // in (0, 90)
  uint32_t max_side = 16384;            // InputError when the packed atlas is larger
};

struct Chart {
  uint32_t mesh = 0;
  std::vector<uint32_t> triangles;  // global triangle ids (GpuSurfaceScene's order: meshes in order)
  glm::uvec2 origin{0};             // padded rectangle, level-0 texels
  glm::uvec2 size{0};               // padded rectangle, level-0 texels (multiples of 2^(levels-1))
};

struct TexelAtlas {
  uint32_t width = 0, height = 0;  // level 0, texels
  uint32_t levels = 1;
  double texels_per_unit = 0.0;
  std::vector<Chart> charts;
  std::vector<uint32_t> chart_of_triangle;             // per global triangle
  std::vector<std::array<glm::dvec2, 3>> corner_uv;    // per global triangle, level-0 texel units
  // Per level L: (width >> L) x (height >> L) triangle ids, row-major, row j = uv.y / 2^L.
  std::vector<std::vector<uint32_t>> triangle_index;

  uint32_t level_width(uint32_t level) const { return width >> level; }
  uint32_t level_height(uint32_t level) const { return height >> level; }
  // Offsets of level L in a buffer holding every level's texels (or tiles) one after the other.
  uint64_t texel_offset(uint32_t level) const;
  uint64_t tile_offset(uint32_t level) const;
  uint64_t texel_count() const { return texel_offset(levels); }
  uint64_t tile_count() const { return tile_offset(levels); }
  uint32_t triangle_at(uint32_t level, uint32_t i, uint32_t j) const { return triangle_index[level][uint64_t(j) * level_width(level) + i]; }
  // Texels the triangle index holds a triangle in (all levels), and those of level 0 whose
  // centre lies in a triangle: the atlas's use of its area.
  uint64_t used_texels() const;
  uint64_t covered_texels_level0() const;
};

// InputError(scene.name, ...) for settings out of range or an atlas beyond max_side.
TexelAtlas build_texel_atlas(const SurfaceScene& scene, const AtlasSettings& settings = {});

// ---- Lookup (what the GPU passes compute in float; the CPU twin in double) -----------------

// Atlas coordinates of the point of `triangle` with barycentric weights `bary`.
glm::dvec2 atlas_uv(const TexelAtlas& atlas, uint32_t triangle, const glm::dvec3& bary);
// Barycentric weights (of `triangle`, possibly outside [0, 1]) of texel (i, j)'s centre at `level`.
glm::dvec3 texel_barycentric(const TexelAtlas& atlas, uint32_t triangle, uint32_t level, uint32_t i, uint32_t j);
// floor(log2(footprint) + bias) clamped to [0, levels - 1]; footprint <= 0 or not finite: 0.
uint32_t select_level(double footprint, double bias, uint32_t levels);

struct Tap {
  glm::uvec2 texel{0};
  double weight = 0.0;  // 0 for a texel without triangle (and the rest renormalized)
};
// The four bilinear taps of uv at `level` (texel coordinates clamped to the level), in the order
// (i0, j0), (i0 + 1, j0), (i0, j0 + 1), (i0 + 1, j0 + 1); a non-finite uv gets four zero taps.
std::array<Tap, 4> bilinear_taps(const TexelAtlas& atlas, const glm::dvec2& uv, uint32_t level);

}  // namespace prismoid::texel
