#pragma once
// Meshlets and their charts for the meshlet shading atlas (Neff et al. 2022, "Meshlets and How
// to Shade Them: A Study on Texture-Space Shading"): plain data and math, no Vulkan.
//
// A meshlet is up to `max_triangles` (84, the paper's) triangles of one mesh. Two clusterings:
//  - Meshoptimizer: meshopt_buildMeshlets (meshoptimizer's clusterizer, the baseline the
//    normal-cone clustering is compared with; Debian's 0.18) per mesh, at most kMeshoptMaxVertices vertices and max_triangles
//    triangles (rounded down to a multiple of 4, as 0.18 requires, at least 4; then cut by
//    triangle order when that is still more than max_triangles), with its cone weight; each
//    meshlet is then charted as below, onto the plane of its area-weighted mean normal, and
//    split in halves (by meshoptimizer's triangle order) until its chart is injective.
//    Degenerate triangles are left out of meshoptimizer's input.
//  - NormalCone (ours, after the paper's 3.1): triangles grown over shared edges while a
//    triangle's normal lies within `max_normal_angle_deg` of the meshlet's seed normal (60
//    degrees, the paper's hard limit for groups over 50 triangles) and its projection neither
//    flips nor overlaps the meshlet's; flat, compact, connected meshlets whose charts waste
//    less of their blocks (MeshletStats measures the difference).
//
// Chart (the paper's pre-charted parametrization, "MSA-UV", with an orthogonal projection in
// place of LSCM; planar_charts.hpp): the meshlet's triangles projected onto a plane
// (NormalCone: its seed's; Meshoptimizer: its area-weighted mean normal's), turned
// so that the minimum-area bounding rectangle of their convex hull is axis-aligned and landscape
// (the paper's gift-wrapping + oriented box step), shifted so that its lower corner is at 0.
// Chart coordinates are in world units; the map is affine per triangle, keeps orientation
// (seen from +normal) and is injective per meshlet. A degenerate triangle (zero area or a
// non-finite corner) is a meshlet of its own: corners at 0, extent 0, normal 0.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::msa {

inline constexpr uint32_t kMaxMeshletTriangles = 84;
inline constexpr uint32_t kMeshoptMaxVertices = 64;

enum class Clustering { Meshoptimizer, NormalCone };
// A meshlet's chart: the orthogonal projection described above, or the least-squares conformal
// map of the same triangles (charts::conformal_chart: the paper's LSCM; a meshlet whose
// conformal chart would flip or overlap keeps its projection): both static (the paper's MSA-UV).
// Or made anew every frame from the camera (the paper's MSA-P and MSA-O, what the FastAtlas
// paper compares against): the meshlet's perspective projection into the image (pixels), or its
// orthographic projection with the camera looking towards the meshlet's centre (world units).
// build_meshlets gives the per-frame kinds the static projection (the GPU replaces it each frame).
enum class Parametrization { Projection, Conformal, Perspective, Orthographic };
// Whether the kind's charts are made every frame.
inline bool per_frame(Parametrization p) { return p == Parametrization::Perspective || p == Parametrization::Orthographic; }
// The --msa-charts word of each: projection, conformal, perspective, orthographic.
const char* parametrization_name(Parametrization p);
// The kind of that word; false for none.
bool parse_parametrization(const std::string& word, Parametrization& out);

struct MeshletSettings {
  Clustering clustering = Clustering::NormalCone;
  Parametrization parametrization = Parametrization::Projection;
  uint32_t max_triangles = kMaxMeshletTriangles;  // 1 .. 126
  double max_normal_angle_deg = 60.0;             // NormalCone: in (0, 90)
  double cone_weight = 0.5;                       // Meshoptimizer: meshopt_buildMeshlets' cone_weight, in [0, 1]
};

struct Meshlet {
  uint32_t mesh = 0;
  std::vector<uint32_t> triangles;  // global triangle ids (GpuSurfaceScene's order)
  glm::dvec2 extent{0.0};           // the chart's rectangle [0, extent.x] x [0, extent.y], extent.x >= extent.y
  glm::dvec3 normal{0.0};           // the chart plane's unit normal (0 for a degenerate triangle's meshlet)
};

struct MeshletSet {
  std::vector<Meshlet> meshlets;
  size_t conformal_fallbacks = 0;  // Conformal: meshlets that kept their projection
  std::vector<uint32_t> meshlet_of_triangle;             // per global triangle
  std::vector<std::array<glm::dvec2, 3>> corner_chart;   // per global triangle: its corners in its meshlet's chart
};

// InputError(scene.name, ...) for settings out of range (every field is checked, whichever the
// clustering) and for a vertex index out of range.
MeshletSet build_meshlets(const SurfaceScene& scene, const MeshletSettings& settings = {});

// What a clustering costs in atlas space: at `texels_per_unit`, each meshlet's block is its
// chart's rectangle scaled, plus a texel of border on each side, rounded up to powers of two
// (msa_class_for). Meshlets of degenerate triangles (extent 0: never drawn) count in
// `meshlets` and the triangle counts only.
struct MeshletStats {
  size_t meshlets = 0;
  double mean_triangles = 0.0;
  uint32_t max_triangles = 0;
  double mean_normal_deviation_deg = 0.0;  // triangle normal vs its meshlet's chart normal, area-weighted
  double chart_fill = 0.0;                 // triangles' chart area / charts' rectangle area
  // Triangles' chart area scaled by min(texels_per_unit, msa_block_scale) (the density the block
  // holds: lower only where the 256-texel side clamps) / blocks' area.
  double block_fill = 0.0;
  // Sampling: a triangle's chart area over its surface area, square-rooted (the texels per unit
  // it gets for each texel per unit asked; a projection gives cos(tilt), a conformal chart its
  // scale): the smallest, and the surface-area-weighted mean.
  double sampling_min = 0.0;
  double sampling_mean = 0.0;
};
// InputError(scene.name, ...) when `set` is not one of the scene's or texels_per_unit is not
// positive and finite.
MeshletStats meshlet_stats(const SurfaceScene& scene, const MeshletSet& set, double texels_per_unit);

// The per-frame charts of `set` for `camera` and a width x height image (the CPU twin of
// shaders/surface/msa/frame_charts.comp, in double): per meshlet, Perspective: its corners'
// image positions in pixels (y down), unless a corner lies nearer than the near plane, then as
// Orthographic: their projection along the direction from the eye to the meshlet's centre (the
// mean of its triangles' corners) onto the plane across it, world units; shifted so that the
// lower corner is at 0.
struct FrameCharts {
  std::vector<std::array<glm::dvec2, 3>> corner_chart;  // per global triangle
  std::vector<glm::dvec2> extent;                       // per meshlet
  std::vector<uint8_t> perspective;                     // per meshlet: 1 when its chart is perspective
};
FrameCharts frame_charts(const SurfaceScene& scene, const MeshletSet& set, const Camera& camera, uint32_t width, uint32_t height,
                         Parametrization kind);

// Block-size arithmetic (the twins of shaders/surface/msa/msa.glsl; shaders/shared/msa.h): a
// chart of `extent` at `density` texels per unit wants w x h texels, w the smallest power of two
// >= ceil(extent.x * density) + 2 clamped to [8, 256], h likewise; its class is
// log2(w / 8) * 6 + log2(h / 8) (6 = PRISMOID_MSA_SIZES). msa_block_scale: the texels per unit
// that fill a class's block with the chart and a texel of border,
// min((w - 2) / extent.x, (h - 2) / extent.y) (1 for extent 0).
uint32_t msa_class_for(const glm::dvec2& extent, double density);
glm::uvec2 msa_class_size(uint32_t size_class);
double msa_block_scale(const glm::dvec2& extent, uint32_t size_class);

}  // namespace prismoid::msa
