// The surface BSDF in float: the twin of renderer/reference/surface_bsdf.cpp (Lambert + GGX with
// Schlick's Fresnel and Smith's height-correlated masking-shadowing, alpha = max(roughness^2,
// PRISMOID_MIN_GGX_ALPHA)). Directions are unit vectors pointing away from the surface.
#ifndef PRISMOID_SURFACE_BSDF_GLSL
#define PRISMOID_SURFACE_BSDF_GLSL

const float PRISMOID_PI = 3.14159265;

// A material at one surface point: the albedo already multiplied by the mesh colour there.
struct ShadingMaterial {
  vec3 albedo;
  vec3 f0;
  float alpha;
  bool specular;  // f0 is not zero: the GGX lobe is evaluated
};

// GGX D for the cosine between the microfacet normal and the shading normal.
float ggx_d(float cos_m, float alpha) {
  if (!(cos_m > 0.0)) return 0.0;
  float a2 = alpha * alpha;
  float denom = cos_m * cos_m * (a2 - 1.0) + 1.0;
  return a2 / (PRISMOID_PI * denom * denom);
}

vec3 schlick_fresnel(vec3 f0, float cos_theta) {
  float c = clamp(1.0 - cos_theta, 0.0, 1.0);
  float c2 = c * c;
  return f0 + (vec3(1.0) - f0) * (c2 * c2 * c);
}

// The GGX lobe F D G2 / (4 cos_o cos_i) for cos_o, cos_i > 0, written as in surface_bsdf.cpp:
// G2 / (4 cos_o cos_i) = 1 / (2 (cos_i a(wo) + cos_o a(wi))), a(w) = sqrt(cos^2 + alpha^2 sin^2).
vec3 ggx_specular(ShadingMaterial m, vec3 n, vec3 wo, vec3 wi, float cos_o, float cos_i) {
  vec3 h = normalize(wo + wi);
  float a2 = m.alpha * m.alpha;
  float a_o = sqrt(cos_o * cos_o + a2 * max(0.0, 1.0 - cos_o * cos_o));
  float a_i = sqrt(cos_i * cos_i + a2 * max(0.0, 1.0 - cos_i * cos_i));
  float visibility = 0.5 / (cos_i * a_o + cos_o * a_i);
  return schlick_fresnel(m.f0, dot(wi, h)) * (ggx_d(dot(n, h), m.alpha) * visibility);
}

// f(wo, wi) cos(theta_i) with the shading normal n; zero when either direction is below it.
vec3 bsdf_cos(ShadingMaterial m, vec3 n, vec3 wo, vec3 wi) {
  float cos_o = dot(n, wo), cos_i = dot(n, wi);
  if (!(cos_o > 0.0) || !(cos_i > 0.0)) return vec3(0.0);
  vec3 f = m.albedo * (1.0 / PRISMOID_PI);
  if (m.specular) f += ggx_specular(m, n, wo, wi, cos_o, cos_i);
  return f * cos_i;
}

#endif
