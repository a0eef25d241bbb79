#pragma once
// A dense set of shading samples for ReSTIR GI (renderer/surface/gi/restir_gi.hpp), for tests and a
// first user-visible path: every texel of one Htex level of every quad of the scene, shaded
// where htex::texel_point puts it (ghost texels and texels on zero-area triangles left out),
// with a table of spatial neighbours found by walking the halfedge adjacency in quad space
// (htex_walk.hpp). Plain data, no Vulkan.
//
// Sample i's slot (reservoir address) is i, its fallback slot i too (in the fallback buffer);
// its viewer is the front side of its triangle (the unit winding normal): the side an
// oriented closed mesh (the furnace, the Cornell box's walls and blocks) is seen from.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "scene/surface_scene.hpp"

namespace prismoid::surface {

inline constexpr uint32_t kNoNeighbour = 0xFFFFFFFFu;

struct GiDenseSetOptions {
  double texels_per_unit = 64.0;  // the Htex layout's level-0 density (htex::LayoutOptions)
  uint32_t level = 0;             // the mip level whose texels are the samples (clamped to each mesh's chain)
  uint32_t max_radius = 2;        // neighbour offsets (di, dj) with max(|di|, |dj|) <= max_radius
};

struct GiDenseSample {
  uint32_t mesh = 0, triangle = 0;  // scene mesh and triangle within it
  uint32_t global_triangle = 0;     // all meshes' triangles in order (GpuSurfaceScene)
  glm::dvec3 bary{0.0};             // of the triangle's corners
  glm::dvec3 position{0.0};         // world
  glm::dvec3 viewer{0.0};           // unit winding normal
  uint32_t edge = 0, i = 0, j = 0;  // the texel: the mesh's edge (quad) and the texel in it
  uint32_t side = 0;                // the quad side n at this level
};

struct GiDenseSet {
  std::vector<GiDenseSample> samples;
  uint32_t max_radius = 0;
  // Per sample, table_width entries: the sample reached by walking each offset, kNoNeighbour
  // where the walk leaves the surface or ends on a texel that is not a sample (or on the sample
  // itself). Offsets in rings: entries [(2r - 1)^2 - 1, (2r + 1)^2 - 1) are the 8 r offsets of
  // ring r, so the first (2 rho + 1)^2 - 1 entries are those within radius rho.
  uint32_t table_width = 0;
  std::vector<uint32_t> neighbours;
  std::vector<glm::ivec2> offsets;  // the offset of each table column
};

// Throws InputError for an invalid scene; std::invalid_argument for bad options (from the layout).
GiDenseSet build_gi_dense_set(const SurfaceScene& scene, const GiDenseSetOptions& options = {});

}  // namespace prismoid::surface
