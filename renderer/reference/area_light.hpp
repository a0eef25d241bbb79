#pragma once
// Direct light from a planar polygonal emitter onto a surface point, in double precision: the
// geometry every shading path shares (shaders/surface/area_light.glsl is its float twin).
//
// Polygons are convex, corners given relative to the shading point (so the point is the
// origin) and wound either way; directions are unit vectors.
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

namespace prismoid::reference {

using Polygon = std::vector<glm::dvec3>;

// The part of the polygon on the side of the plane through the origin that `normal` points to
// (dot(normal, p) >= 0), by Sutherland-Hodgman: one plane adds at most one corner.
Polygon clip_to_hemisphere(const Polygon& polygon, const glm::dvec3& normal);

// The polygon's projected solid angle, the integral of dot(normal, w) over the directions w it
// covers, for a polygon on the non-negative side of `normal` (clip it first): Lambert's formula
// (Photometria, 1760), |1/2 sum_i theta_i dot(normal, gamma_i)|, theta_i the angle between
// corners i and i+1 seen from the origin and gamma_i the unit normal of the plane through them.
// `abs_sum` = 1/2 sum_i |theta_i dot(normal, gamma_i)| bounds the cancellation in the sum
// (value / abs_sum is its condition).
struct ProjectedSolidAngle {
  double value = 0.0;
  double abs_sum = 0.0;
};
ProjectedSolidAngle projected_solid_angle(const Polygon& polygon, const glm::dvec3& normal);

// Solid angle of the triangle (a, b, c) seen from the origin (Van Oosterom & Strackee 1983,
// "The solid angle of a plane triangle"): 2 atan2(|a.(b x c)|, |a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|).
double triangle_solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c);

// An integrand over directions (RGB), e.g. radiance times BSDF times cosine.
using DirectionalIntegrand = std::function<glm::dvec3(const glm::dvec3& direction)>;

// The fixed rule of the forward shading (PRISMOID_AREA_SPECULAR_SUBDIVISION): the polygon is
// fanned into triangles from its first corner, each cut into n^2 congruent sub-triangles, and
// each sub-triangle contributes its solid angle times the integrand towards its centroid.
// Exact for integrands constant over each sub-triangle; the error falls as 1/n^2 for smooth
// ones. `nodes` (optional) receives the number of sub-triangles evaluated.
glm::dvec3 subdivision_rule(const Polygon& polygon, uint32_t n, const DirectionalIntegrand& f, uint32_t* nodes = nullptr);

// The integral of f over the polygon's directions to about `tolerance` (absolute), for f smooth
// over the polygon: Radon's degree-5 rule in the area measure of each fan triangle, which is
// split in 4 until its estimate and its children's agree, at most `max_depth` levels deep.
glm::dvec3 adaptive_integral(const Polygon& polygon, const DirectionalIntegrand& f, double tolerance, uint32_t max_depth = 10);

}  // namespace prismoid::reference
