#pragma once
// The surface BSDF every shading path uses (scene/surface_scene.hpp states it): a Lambertian
// lobe plus a GGX microfacet lobe (Walter, Marschner, Li & Torrance 2007) with Schlick's
// Fresnel, Smith's height-correlated masking-shadowing (Heitz 2014, "Understanding the
// masking-shadowing function in microfacet-based BRDFs") and sampling of the visible normals
// (Heitz 2018, "Sampling the GGX distribution of visible normals"). Double precision.
//
// All directions are unit vectors in the local shading frame (z = shading normal), pointing
// away from the surface. Functions return 0 (never NaN) for directions below the surface.
#include <optional>

#include <glm/vec3.hpp>

namespace prismoid::reference {

// GGX normal distribution D(m) (integrates to 1 against cos(theta_m) over the hemisphere).
double ggx_d(const glm::dvec3& m, double alpha);
// Smith's Lambda for GGX; G1 = 1 / (1 + Lambda); G2 (height-correlated) = 1 / (1 + L(o) + L(i)).
double ggx_lambda(const glm::dvec3& w, double alpha);
double ggx_g1(const glm::dvec3& w, double alpha);
double ggx_g2(const glm::dvec3& wo, const glm::dvec3& wi, double alpha);
// A microfacet normal drawn from the distribution of normals visible from wo,
// D_wo(m) = G1(wo) max(0, wo.m) D(m) / wo.z, from two uniform numbers in [0, 1).
glm::dvec3 sample_ggx_visible_normal(const glm::dvec3& wo, double alpha, double u1, double u2);
double ggx_visible_normal_pdf(const glm::dvec3& wo, const glm::dvec3& m, double alpha);
glm::dvec3 schlick_fresnel(const glm::dvec3& f0, double cos_theta);

// A material at one surface point: albedo already multiplied by the mesh colour there,
// alpha = max(roughness^2, kMinGgxAlpha).
struct BsdfParams {
  glm::dvec3 albedo{0.0};
  glm::dvec3 specular_f0{0.0};
  double alpha = 1.0;
};
BsdfParams bsdf_params(const glm::dvec3& albedo, const glm::dvec3& specular_f0, double roughness);

// f(wo, wi) = albedo / pi + F(wi.h) D(h) G2(wo, wi) / (4 wo.z wi.z).
glm::dvec3 bsdf_eval(const BsdfParams& p, const glm::dvec3& wo, const glm::dvec3& wi);
// The probability of choosing the specular lobe when sampling: mean(F0) / (mean(F0) + mean(albedo)).
double specular_lobe_probability(const BsdfParams& p);
// Solid-angle density with which sample_bsdf draws wi: a mixture of cosine-weighted
// hemisphere sampling and visible-normal sampling reflected about the normal.
double bsdf_pdf(const BsdfParams& p, const glm::dvec3& wo, const glm::dvec3& wi);

struct BsdfSample {
  glm::dvec3 wi{0.0};
  glm::dvec3 weight{0.0};  // f(wo, wi) wi.z / pdf
  double pdf = 0.0;
};
// Draws wi from three uniform numbers. nullopt when the path legitimately ends here: the
// material reflects nothing, wo is below the surface, or the microfacet reflection lands below
// it (the energy single scattering loses). A sample whose pdf comes out 0 or not finite
// (numerically, e.g. a grazing microfacet) is returned with pdf 0 and weight 0 so that the
// caller can count it.
std::optional<BsdfSample> sample_bsdf(const BsdfParams& p, const glm::dvec3& wo, double u_lobe, double u1, double u2);

}  // namespace prismoid::reference
