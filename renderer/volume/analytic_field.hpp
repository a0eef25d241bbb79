#pragma once
// Analytic scalar fields in world coordinates, for marching inside intervals (Tricard 2024,
// section 3.2): fields that are not linear in a cell, so the fragment must march its interval.
// The double twin of shaders/volume/analytic_field.glsl; both read the same parameters.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/volume/sampled_grid.hpp"
#include "scene/tet_mesh_fwd.hpp"
#include "shaders/shared/volume.h"

namespace prismoid::volume {

enum class FieldKind : uint32_t {
  Linear = PRISMOID_FIELD_LINEAR,
  MarschnerLobb = PRISMOID_FIELD_MARSCHNER_LOBB,
  GaussianBlobs = PRISMOID_FIELD_GAUSSIAN_BLOBS,
  Grid = PRISMOID_FIELD_GRID,  // not analytic: samples, interpolated trilinearly (sampled_grid.hpp)
};

struct AnalyticField {
  std::string name;
  FieldKind kind = FieldKind::MarschnerLobb;
  std::vector<glm::dvec4> params;  // at most PRISMOID_FIELD_MAX_PARAMS; meaning per kind in volume.h
  // FieldKind::Grid only (its params are empty; the renderer derives the shader's from it).
  // Shared: settings that name the field are copied per frame, the samples are not.
  std::shared_ptr<const SampledGrid> grid;
};

double evaluate(const AnalyticField& field, const glm::dvec3& p);
glm::dvec3 gradient(const AnalyticField& field, const glm::dvec3& p);
// An upper bound, over all points and unit directions u, of |d^2/ds^2 f(p + s u)| (the
// Hessian's spectral norm): the midpoint rule's error over a segment of length L in steps of
// h is at most L h^2 / 24 times this. Infinite for a grid: its gradient jumps at voxel faces.
double second_derivative_bound(const AnalyticField& field);

// The same field in coordinates whose 0 lies at `origin` (g(q) = f(q + origin)), its
// parameters moved exactly in double, for kinds with a position to move (linear: the value
// at 0; blobs: the centres; a grid: a copy of its samples with the origin moved).
// Marschner-Lobb is defined about the world origin: nullopt.
// Marching evaluates fields in float relative to the mesh's centre this way.
std::optional<AnalyticField> translated(const AnalyticField& field, const glm::dvec3& origin);
// The same field in coordinates q with g(q) = f(origin + scale * q) (scale > 0): the frame's
// units (frame/frame_units.hpp). Linear fields and blobs only (a gradient scaled, centres and
// widths moved and scaled); nullopt for the others (Marschner-Lobb, grids: the shader places
// them).
std::optional<AnalyticField> placed(const AnalyticField& field, const glm::dvec3& origin, double scale);

// Marschner & Lobb (1994): (1 - sin(pi z / 2) + alpha (1 + cos(2 pi f_M cos(pi r / 2)))) /
// (2 (1 + alpha)), r = sqrt(x^2 + y^2), on [-1, 1]^3 with values in [0, 1].
AnalyticField marschner_lobb(double f_m = 6.0, double alpha = 0.25);
// Sum of exp(-|p - c|^2 / (2 w^2)) over blobs (c, w): one blob's level sets are spheres.
AnalyticField gaussian_blobs(const std::vector<glm::dvec4>& blobs);
AnalyticField linear_field(const glm::dvec3& gradient, double value_at_origin);
// A sampled grid as a field to march (FieldKind::Grid), named as the grid is.
AnalyticField grid_field(std::shared_ptr<const SampledGrid> grid);
// The field at the samples of a dims grid spanning [lo, hi] (corners are samples).
SampledGrid sample_onto_grid(const AnalyticField& field, const glm::uvec3& dims, const glm::dvec3& lo, const glm::dvec3& hi);

// The named fields of the CLI's `field:NAME` datasets (field_names()); InputError otherwise.
AnalyticField field_from_name(const std::string& name);
std::vector<std::string> field_names();
// Throws InputError(field.name, ...) for a wrong parameter count or non-finite/invalid values.
void validate(const AnalyticField& field);

// A Kuhn-split box [-1, 1]^3 of n^3 cubes bounding the field: point scalars and point
// extinction are the field at the points (scaled by density_scale for the extinction), cell
// extinction its value at the centroid; so the non-marching modes render its linear interpolant.
TetMesh make_field_mesh(const AnalyticField& field, uint32_t n, double density_scale = 1.0);

}  // namespace prismoid::volume
