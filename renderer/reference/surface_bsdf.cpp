#include "renderer/reference/surface_bsdf.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>

#include "scene/surface_scene.hpp"

namespace prismoid::reference {

namespace {

constexpr double kPi = std::numbers::pi;

double mean(const glm::dvec3& v) { return (v.x + v.y + v.z) / 3.0; }

// Cosine-weighted direction on the upper hemisphere: a uniform point on the unit disk
// (Shirley & Chiu's concentric map) lifted onto the hemisphere.
glm::dvec3 cosine_hemisphere(double u1, double u2) {
  const double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
  double r = 0.0, phi = 0.0;
  if (a != 0.0 || b != 0.0) {
    if (std::abs(a) > std::abs(b)) {
      r = a;
      phi = (kPi / 4.0) * (b / a);
    } else {
      r = b;
      phi = (kPi / 2.0) - (kPi / 4.0) * (a / b);
    }
  }
  const double x = r * std::cos(phi), y = r * std::sin(phi);
  return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
}

// Density of wi from the specular lobe: the visible-normal density of the half vector times
// the Jacobian of reflection, 1 / (4 wo.h).
double specular_pdf(const BsdfParams& p, const glm::dvec3& wo, const glm::dvec3& wi) {
  const glm::dvec3 sum = wo + wi;
  const double len = glm::length(sum);
  if (!(len > 0.0)) return 0.0;
  const glm::dvec3 h = sum / len;
  const double wo_h = glm::dot(wo, h);
  if (!(wo_h > 0.0)) return 0.0;
  return ggx_visible_normal_pdf(wo, h, p.alpha) / (4.0 * wo_h);
}

}  // namespace

double ggx_d(const glm::dvec3& m, double alpha) {
  if (!(m.z > 0.0)) return 0.0;
  const double a2 = alpha * alpha;
  const double c2 = m.z * m.z;
  const double denom = c2 * (a2 - 1.0) + 1.0;
  return a2 / (kPi * denom * denom);
}

double ggx_lambda(const glm::dvec3& w, double alpha) {
  if (!(w.z > 0.0)) return std::numeric_limits<double>::infinity();
  const double tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
  return 0.5 * (std::sqrt(1.0 + alpha * alpha * tan2) - 1.0);
}

double ggx_g1(const glm::dvec3& w, double alpha) {
  if (!(w.z > 0.0)) return 0.0;
  return 1.0 / (1.0 + ggx_lambda(w, alpha));
}

double ggx_g2(const glm::dvec3& wo, const glm::dvec3& wi, double alpha) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  return 1.0 / (1.0 + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

glm::dvec3 sample_ggx_visible_normal(const glm::dvec3& wo, double alpha, double u1, double u2) {
  // Stretch to the configuration where the roughness is 1, sample the projected area of the
  // visible hemisphere there (a disk whose far half is squashed by the view's inclination),
  // then unstretch.
  const glm::dvec3 v = glm::normalize(glm::dvec3(alpha * wo.x, alpha * wo.y, wo.z));
  const double len2 = v.x * v.x + v.y * v.y;
  const glm::dvec3 t1 = len2 > 0.0 ? glm::dvec3(-v.y, v.x, 0.0) / std::sqrt(len2) : glm::dvec3(1.0, 0.0, 0.0);
  const glm::dvec3 t2 = glm::cross(v, t1);
  const double r = std::sqrt(u1);
  const double phi = 2.0 * kPi * u2;
  const double p1 = r * std::cos(phi);
  double p2 = r * std::sin(phi);
  const double s = 0.5 * (1.0 + v.z);
  p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * p2;
  const glm::dvec3 n = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2)) * v;
  return glm::normalize(glm::dvec3(alpha * n.x, alpha * n.y, std::max(0.0, n.z)));
}

double ggx_visible_normal_pdf(const glm::dvec3& wo, const glm::dvec3& m, double alpha) {
  if (!(wo.z > 0.0)) return 0.0;
  const double wo_m = glm::dot(wo, m);
  if (!(wo_m > 0.0)) return 0.0;
  // G1(wo) / wo.z = 2 / (wo.z + a(wo)), a as in bsdf_eval: finite for grazing wo.
  const double a_o = std::sqrt(wo.z * wo.z + alpha * alpha * (wo.x * wo.x + wo.y * wo.y));
  const double pdf = 2.0 * wo_m * ggx_d(m, alpha) / (wo.z + a_o);
  return std::isfinite(pdf) ? pdf : 0.0;
}

glm::dvec3 schlick_fresnel(const glm::dvec3& f0, double cos_theta) {
  const double c = std::clamp(1.0 - cos_theta, 0.0, 1.0);
  const double c2 = c * c;
  return f0 + (glm::dvec3(1.0) - f0) * (c2 * c2 * c);
}

BsdfParams bsdf_params(const glm::dvec3& albedo, const glm::dvec3& specular_f0, double roughness) {
  return {albedo, specular_f0, std::max(roughness * roughness, kMinGgxAlpha)};
}

glm::dvec3 bsdf_eval(const BsdfParams& p, const glm::dvec3& wo, const glm::dvec3& wi) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return glm::dvec3(0.0);
  glm::dvec3 f = p.albedo / kPi;
  if (p.specular_f0 != glm::dvec3(0.0)) {
    const glm::dvec3 h = glm::normalize(wo + wi);
    // G2 / (4 wo.z wi.z) = 1 / (2 (wi.z a(wo) + wo.z a(wi))) with a(w) = w.z sqrt(1 + alpha^2 tan^2):
    // the same quantity without the 0 * infinity of a grazing direction's Lambda.
    const double a2 = p.alpha * p.alpha;
    const double a_o = std::sqrt(wo.z * wo.z + a2 * (wo.x * wo.x + wo.y * wo.y));
    const double a_i = std::sqrt(wi.z * wi.z + a2 * (wi.x * wi.x + wi.y * wi.y));
    const double visibility = 0.5 / (wi.z * a_o + wo.z * a_i);
    f += schlick_fresnel(p.specular_f0, glm::dot(wi, h)) * (ggx_d(h, p.alpha) * visibility);
  }
  // Both directions grazing to within ~1e-300 overflow; such a pair reflects nothing measurable.
  if (!std::isfinite(f.x) || !std::isfinite(f.y) || !std::isfinite(f.z)) return glm::dvec3(0.0);
  return f;
}

double specular_lobe_probability(const BsdfParams& p) {
  const double s = mean(p.specular_f0), d = mean(p.albedo);
  return s + d > 0.0 ? s / (s + d) : 0.0;
}

double bsdf_pdf(const BsdfParams& p, const glm::dvec3& wo, const glm::dvec3& wi) {
  if (!(wo.z > 0.0) || !(wi.z > 0.0)) return 0.0;
  const double ps = specular_lobe_probability(p);
  double pdf = (1.0 - ps) * wi.z / kPi;
  if (ps > 0.0) pdf += ps * specular_pdf(p, wo, wi);
  return pdf;
}

std::optional<BsdfSample> sample_bsdf(const BsdfParams& p, const glm::dvec3& wo, double u_lobe, double u1, double u2) {
  if (!(wo.z > 0.0)) return std::nullopt;
  if (mean(p.specular_f0) + mean(p.albedo) <= 0.0) return std::nullopt;
  const double ps = specular_lobe_probability(p);
  BsdfSample s;
  if (u_lobe < ps) {
    const glm::dvec3 m = sample_ggx_visible_normal(wo, p.alpha, u1, u2);
    s.wi = 2.0 * glm::dot(wo, m) * m - wo;
  } else {
    s.wi = cosine_hemisphere(u1, u2);
  }
  if (!(s.wi.z > 0.0)) return std::nullopt;
  s.wi = glm::normalize(s.wi);
  s.pdf = bsdf_pdf(p, wo, s.wi);
  if (!(s.pdf > 0.0) || !std::isfinite(s.pdf)) return BsdfSample{s.wi, glm::dvec3(0.0), 0.0};
  s.weight = bsdf_eval(p, wo, s.wi) * (s.wi.z / s.pdf);
  return s;
}

}  // namespace prismoid::reference
