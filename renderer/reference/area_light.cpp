#include "renderer/reference/area_light.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace prismoid::reference {

namespace {

double max_abs(const glm::dvec3& v) { return std::max(std::abs(v.x), std::max(std::abs(v.y), std::abs(v.z))); }

glm::dvec3 node(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const DirectionalIntegrand& f) {
  const double omega = triangle_solid_angle(a, b, c);
  const glm::dvec3 centroid = a + b + c;
  const double len = glm::length(centroid);
  if (!(omega > 0.0) || !(len > 0.0)) return glm::dvec3(0.0);
  return omega * f(centroid / len);
}

// Radon's 7-point rule (1948), exact for polynomials of degree 5 on a triangle, applied in the
// area measure of the flat triangle: dw = |n.y| / |y|^3 dA for a point y of the emitter's plane
// seen from the origin.
glm::dvec3 radon_rule(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const DirectionalIntegrand& f) {
  const double s15 = std::sqrt(15.0);
  const double p1 = (6.0 - s15) / 21.0, q1 = 1.0 - 2.0 * p1, w1 = (155.0 - s15) / 1200.0;
  const double p2 = (6.0 + s15) / 21.0, q2 = 1.0 - 2.0 * p2, w2 = (155.0 + s15) / 1200.0;
  const glm::dvec3 cross = glm::cross(b - a, c - a);
  const double area2 = glm::length(cross);  // twice the area
  if (!(area2 > 0.0)) return glm::dvec3(0.0);
  const glm::dvec3 n = cross / area2;
  auto at = [&](double u, double v, double w) {
    const glm::dvec3 y = u * a + v * b + w * c;
    const double d = glm::length(y);
    if (!(d > 0.0)) return glm::dvec3(0.0);
    return f(y / d) * (std::abs(glm::dot(n, y)) / (d * d * d));
  };
  glm::dvec3 sum = (9.0 / 40.0) * at(1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0);
  sum += w1 * (at(p1, p1, q1) + at(p1, q1, p1) + at(q1, p1, p1));
  sum += w2 * (at(p2, p2, q2) + at(p2, q2, p2) + at(q2, p2, p2));
  return 0.5 * area2 * sum;
}

glm::dvec3 refine(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& coarse,
                  const DirectionalIntegrand& f, double tolerance, uint32_t depth, uint32_t max_depth) {
  const glm::dvec3 ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  const glm::dvec3 e[4] = {radon_rule(a, ab, ca, f), radon_rule(ab, b, bc, f), radon_rule(ca, bc, c, f), radon_rule(ab, bc, ca, f)};
  const glm::dvec3 fine = e[0] + e[1] + e[2] + e[3];
  if (depth >= max_depth || max_abs(fine - coarse) <= tolerance) return fine;
  const double t = tolerance / 4.0;
  return refine(a, ab, ca, e[0], f, t, depth + 1, max_depth) + refine(ab, b, bc, e[1], f, t, depth + 1, max_depth) +
         refine(ca, bc, c, e[2], f, t, depth + 1, max_depth) + refine(ab, bc, ca, e[3], f, t, depth + 1, max_depth);
}

}  // namespace

Polygon clip_to_hemisphere(const Polygon& polygon, const glm::dvec3& normal) {
  Polygon out;
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    const glm::dvec3& a = polygon[i];
    const glm::dvec3& b = polygon[(i + 1) % n];
    const double da = glm::dot(normal, a), db = glm::dot(normal, b);
    if (da >= 0.0) out.push_back(a);
    if ((da >= 0.0) != (db >= 0.0)) {  // cut from the corner below: the same point either way along the edge
      const glm::dvec3& below = da < 0.0 ? a : b;
      const glm::dvec3& above = da < 0.0 ? b : a;
      const double d_below = std::min(da, db), d_above = std::max(da, db);
      out.push_back(below + (above - below) * (d_below / (d_below - d_above)));
    }
  }
  return out;
}

ProjectedSolidAngle projected_solid_angle(const Polygon& polygon, const glm::dvec3& normal) {
  ProjectedSolidAngle r;
  if (polygon.size() < 3) return r;
  double sum = 0.0, abs_sum = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const glm::dvec3& a = polygon[i];
    const glm::dvec3& b = polygon[(i + 1) % polygon.size()];
    // a x b, from the shorter corner and the edge (as shaders/surface/area_light.glsl).
    const glm::dvec3 c = glm::dot(a, a) <= glm::dot(b, b) ? glm::cross(a, b - a) : glm::cross(a - b, b);
    const double len = glm::length(c);
    if (!(len > 0.0)) continue;  // corners along one ray (or a corner at the origin): no area
    const double theta = std::atan2(len, glm::dot(a, b));
    const double term = theta * glm::dot(normal, c) / len;
    sum += term;
    abs_sum += std::abs(term);
  }
  r.value = 0.5 * std::abs(sum);
  r.abs_sum = 0.5 * abs_sum;
  return r;
}

double triangle_solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double triple = std::abs(glm::dot(a, glm::cross(b - a, c - a)));  // = |a.(b x c)|
  const double denom = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
  return 2.0 * std::atan2(triple, denom);
}

glm::dvec3 subdivision_rule(const Polygon& polygon, uint32_t n, const DirectionalIntegrand& f, uint32_t* nodes) {
  glm::dvec3 sum(0.0);
  uint32_t count = 0;
  for (size_t k = 1; k + 1 < polygon.size(); ++k) {
    const glm::dvec3 a = polygon[0];
    const glm::dvec3 e1 = (polygon[k] - a) / double(n), e2 = (polygon[k + 1] - a) / double(n);
    for (uint32_t i = 0; i < n; ++i)
      for (uint32_t j = 0; i + j < n; ++j) {
        const glm::dvec3 p = a + double(i) * e1 + double(j) * e2;
        sum += node(p, p + e1, p + e2, f);
        ++count;
        if (i + j + 2 <= n) {
          sum += node(p + e1, p + e1 + e2, p + e2, f);
          ++count;
        }
      }
  }
  if (nodes) *nodes = count;
  return sum;
}

glm::dvec3 adaptive_integral(const Polygon& polygon, const DirectionalIntegrand& f, double tolerance, uint32_t max_depth) {
  glm::dvec3 sum(0.0);
  const size_t fans = polygon.size() >= 3 ? polygon.size() - 2 : 0;
  for (size_t k = 1; k + 1 < polygon.size(); ++k) {
    const glm::dvec3 &a = polygon[0], &b = polygon[k], &c = polygon[k + 1];
    sum += refine(a, b, c, radon_rule(a, b, c, f), f, tolerance / double(fans), 0, max_depth);
  }
  return sum;
}

}  // namespace prismoid::reference
