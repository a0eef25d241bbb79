#pragma once
// Meshlets and their charts for the meshlet shading atlas (Neff et al. 2022, "Meshlets and How
// to Shade Them", shared/papers): plain data and math, no Vulkan.
//
// A meshlet is up to `max_triangles` (84, the paper's) triangles of one mesh. Two clusterings:
//  - Meshoptimizer: meshopt_buildMeshlets (meshoptimizer's clusterizer, the starting
//    point) with its cone weight; each meshlet is then charted as below and split in halves
//    (by triangle order) until its chart is injective.
//  - NormalCone (ours, after the paper's 3.1): triangles grown over shared edges while a
//    triangle's normal lies within `max_normal_angle_deg` of the meshlet's seed normal (60
//    degrees, the paper's hard limit for groups over 50 triangles) and its projection neither
//    flips nor overlaps the meshlet's; flat, compact, connected meshlets whose charts waste
//    less of their blocks (MeshletStats measures the difference).
//
// Chart (the paper's pre-charted parametrization, "MSA-UV", with an orthogonal projection in
// place of LSCM): the meshlet's triangles projected onto the plane of its seed's normal, turned
// so that the minimum-area bounding rectangle of their convex hull is axis-aligned and landscape
// (the paper's gift-wrapping + oriented box step), shifted so that its lower corner is at 0.
// Chart coordinates are in world units; the map is affine per triangle and injective per meshlet.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>

#include "scene/surface_scene.hpp"

namespace prismoid::msa {

inline constexpr uint32_t kMaxMeshletTriangles = 84;

enum class Clustering { Meshoptimizer, NormalCone };

struct MeshletSettings {
  Clustering clustering = Clustering::NormalCone;
  uint32_t max_triangles = kMaxMeshletTriangles;  // 1 .. 126
  double max_normal_angle_deg = 60.0;             // NormalCone: in (0, 90)
  double cone_weight = 0.5;                       // Meshoptimizer: meshopt_buildMeshlets' cone_weight
};

struct Meshlet {
  uint32_t mesh = 0;
  std::vector<uint32_t> triangles;  // global triangle ids (GpuSurfaceScene's order)
  glm::dvec2 extent{0.0};           // the chart's rectangle [0, extent.x] x [0, extent.y], extent.x >= extent.y
};

struct MeshletSet {
  std::vector<Meshlet> meshlets;
  std::vector<uint32_t> meshlet_of_triangle;             // per global triangle
  std::vector<std::array<glm::dvec2, 3>> corner_chart;   // per global triangle: its corners in its meshlet's chart
};

// InputError(scene.name, ...) for settings out of range.
MeshletSet build_meshlets(const SurfaceScene& scene, const MeshletSettings& settings = {});

// What a clustering costs in atlas space: at `texels_per_unit`, each meshlet's block is its
// chart's rectangle scaled, plus a texel of border on each side, rounded up to powers of two.
struct MeshletStats {
  size_t meshlets = 0;
  double mean_triangles = 0.0;
  uint32_t max_triangles = 0;
  double mean_normal_deviation_deg = 0.0;  // triangle normal vs the meshlet's seed normal, area-weighted
  double chart_fill = 0.0;                 // triangles' chart area / charts' rectangle area
  double block_fill = 0.0;                 // triangles' chart area (scaled) / blocks' area
};
MeshletStats meshlet_stats(const SurfaceScene& scene, const MeshletSet& set, double texels_per_unit);

}  // namespace prismoid::msa
