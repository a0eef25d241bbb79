#pragma once
// Planar charts of triangle meshes: plain data and math, no Vulkan. Shared by the texel shading
// atlas (texel_atlas.hpp) and the meshlet shading atlas's meshlets (meshlets.hpp).
//
// A chart is a set of triangles of one mesh projected orthogonally onto one plane (unit normal
// `normal`), turned so that the minimum-area bounding rectangle of their convex hull (rotating
// calipers over the hull's edges) is axis-aligned and landscape, and shifted so that the
// rectangle's lower corner is at 0: it spans [0, extent.x] x [0, extent.y], extent.x >= extent.y.
// Coordinates are in world units; the map is affine per triangle, keeps every triangle's
// orientation (counter-clockwise seen from +normal stays counter-clockwise) and is injective on
// the chart (no two triangles' images overlap in their interiors).
//
// A degenerate triangle (|cross| <= kDegenerateTriangle * (longest edge)^2, or a non-finite
// corner) has no plane: it forms a "point-like" chart of its own, all corners at 0, extent 0,
// normal 0.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/surface_scene.hpp"

namespace prismoid::charts {

inline constexpr double kDegenerateTriangle = 1e-12;
// A triangle joins a chart only when its projection keeps at least this fraction of its area,
// with positive orientation.
inline constexpr double kMinProjectedArea = 1e-9;

// One triangle of the scene, in global order (meshes one after the other).
struct TriangleGeometry {
  uint32_t mesh = 0;
  std::array<glm::dvec3, 3> p{};
  glm::dvec3 normal{0.0};  // unit, from the winding (p1 - p0) x (p2 - p0); 0 when degenerate
  double area = 0.0;       // 0 when degenerate
  bool degenerate = true;
};

// InputError(scene.name, ...) for a vertex index out of range or more than 2^32 - 1 triangles.
std::vector<TriangleGeometry> triangle_geometry(const SurfaceScene& scene);

struct PlanarChart {
  uint32_t mesh = 0;
  std::vector<uint32_t> triangles;                  // global triangle ids, ascending
  std::vector<std::array<glm::dvec2, 3>> corners;   // per triangles[k]: its corners in the chart
  glm::dvec2 extent{0.0};
  glm::dvec3 normal{0.0};                           // the projection plane's unit normal (0: point-like)
  bool point_like() const { return normal == glm::dvec3(0.0); }
};

// Charts grown over shared edges (any number of triangles sharing an edge are neighbours), each
// from the lowest triangle not yet in a chart (its seed, whose plane it is projected onto),
// breadth first. A triangle joins when it is not degenerate, its normal lies within
// `max_normal_angle_deg` of the seed's, its projection keeps kMinProjectedArea of its area with
// positive orientation and does not overlap a triangle already in the chart, and the chart has
// fewer than `max_triangles`. Charts come in the order of their seeds; never across meshes.
// `geometry` = triangle_geometry(scene). InputError(scene.name, ...) for max_triangles 0 or an
// angle outside (0, 90) (callers check their settings first with their own words).
std::vector<PlanarChart> grow_planar_charts(const SurfaceScene& scene, const std::vector<TriangleGeometry>& geometry,
                                            uint32_t max_triangles, double max_normal_angle_deg);

// The chart of a given set of triangles (global ids, one mesh, no repeats), projected onto the
// plane of their area-weighted mean normal (the first triangle's when that mean vanishes). One
// degenerate triangle alone gives a point-like chart. nullopt when the set is empty, mixes
// meshes, holds a degenerate triangle among others, or when some triangle's projection flips or
// keeps less than kMinProjectedArea of its area, or two projections overlap.
std::optional<PlanarChart> chart_triangles(const std::vector<TriangleGeometry>& geometry, std::vector<uint32_t> triangles);

// The same triangles with least-squares conformal coordinates (Lévy, Petitjean, Ray & Maillot
// 2002, "Least Squares Conformal Maps", the meshlet shading atlas paper's pre-charted LSCM), in
// place of the projection: vertices are the triangles' corners that coincide exactly (one mesh's
// shared vertices); the two corners farthest apart in `chart` are pinned where `chart` has them;
// the rest solve the conformal energy's normal equations (dense Cholesky: a chart holds at most
// a few hundred corners). The result is scaled so that its area equals the triangles' surface
// area (on average a texel per unit asks for one texel per unit of surface; the projection gives
// cos(tilt) of that), then turned and shifted as a planar chart; `normal` stays `chart`'s.
// nullopt (callers keep the projection) when the system is singular (e.g. a meshlet in two
// pieces), when the conformal chart flips, shrinks below kMinProjectedArea or overlaps anywhere,
// or when it samples its worst triangle less densely than `chart` does (the square root of chart
// area over surface area, smallest over the triangles: a conformal chart is never a worse
// sampling than the projection it replaces). A point-like or single-triangle chart is returned
// as it is.
std::optional<PlanarChart> conformal_chart(const std::vector<TriangleGeometry>& geometry, const PlanarChart& chart);

}  // namespace prismoid::charts
