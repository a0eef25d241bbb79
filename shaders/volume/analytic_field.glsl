// Analytic fields (in the coordinates FrameUniforms.field_origin describes): the float twin of renderer/volume/analytic_field.cpp,
// which documents each kind; parameters as in FrameUniforms.field / field_params. Also the
// sampled grid (grid_field.glsl), which brings its buffer's binding.
#ifndef PRISMOID_ANALYTIC_FIELD_GLSL
#define PRISMOID_ANALYTIC_FIELD_GLSL

#include "grid_field.glsl"

const float kFieldPi = 3.14159265358979;

float analytic_field(uint kind, uint count, vec4 params[PRISMOID_FIELD_MAX_PARAMS], vec3 p) {
  if (kind == PRISMOID_FIELD_GRID) return grid_field(params, p);
  if (kind == PRISMOID_FIELD_LINEAR) return dot(params[0].xyz, p) + params[0].w;
  if (kind == PRISMOID_FIELD_MARSCHNER_LOBB) {
    float f_m = params[0].x, alpha = params[0].y;
    float radial = cos(2.0 * kFieldPi * f_m * cos(kFieldPi * length(p.xy) / 2.0));
    return (1.0 - sin(kFieldPi * p.z / 2.0) + alpha * (1.0 + radial)) / (2.0 * (1.0 + alpha));
  }
  float sum = 0.0;
  for (uint i = 0u; i < count; ++i) {
    vec3 d = p - params[i].xyz;
    sum += exp(-dot(d, d) / (2.0 * params[i].w * params[i].w));
  }
  return sum;
}

vec3 analytic_gradient(uint kind, uint count, vec4 params[PRISMOID_FIELD_MAX_PARAMS], vec3 p) {
  if (kind == PRISMOID_FIELD_GRID) return grid_gradient(params, p);
  if (kind == PRISMOID_FIELD_LINEAR) return params[0].xyz;
  if (kind == PRISMOID_FIELD_MARSCHNER_LOBB) {
    float f_m = params[0].x, alpha = params[0].y;
    float r = length(p.xy);
    float g = 2.0 * kFieldPi * f_m * cos(kFieldPi * r / 2.0);
    float sin_over_r = r > 1e-12 ? sin(kFieldPi * r / 2.0) / r : kFieldPi / 2.0;
    float radial = alpha * sin(g) * kFieldPi * kFieldPi * f_m * sin_over_r;
    return vec3(radial * p.x, radial * p.y, -kFieldPi / 2.0 * cos(kFieldPi * p.z / 2.0)) / (2.0 * (1.0 + alpha));
  }
  vec3 sum = vec3(0.0);
  for (uint i = 0u; i < count; ++i) {
    vec3 d = p - params[i].xyz;
    float w2 = params[i].w * params[i].w;
    sum -= d / w2 * exp(-dot(d, d) / (2.0 * w2));
  }
  return sum;
}

#endif
