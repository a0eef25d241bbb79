// A sampled grid (PRISMOID_FIELD_GRID): the float twin of renderer/volume/sampled_grid.cpp,
// parameters as volume.h describes. Interpolated here from the 8 samples in float, not by a
// 3D image's filtering: that interpolates with low-precision fixed-point weights (8 bits of
// fraction on NVIDIA), far coarser than the float rounding the tests allow.
#ifndef PRISMOID_GRID_FIELD_GLSL
#define PRISMOID_GRID_FIELD_GLSL

layout(std430, set = 0, binding = PRISMOID_BINDING_FIELD_GRID) readonly buffer FieldGrid { float grid_values[]; };

struct GridVoxel {
  bool inside;
  uvec3 lo, hi;  // samples on the voxel's lower and upper faces (equal on an axis of one sample)
  vec3 t;        // fractions inside the voxel
};

GridVoxel grid_locate(vec4 params[PRISMOID_FIELD_MAX_PARAMS], vec3 p) {
  GridVoxel v;
  v.inside = false;
  v.lo = uvec3(0u);
  v.hi = uvec3(0u);
  v.t = vec3(0.0);
  vec3 u = (p - params[0].xyz) * params[1].xyz;
  vec3 last = params[2].xyz - 1.0;
  // Written so that NaN positions are outside.
  if (!(all(greaterThanEqual(u, vec3(0.0))) && all(lessThanEqual(u, last)))) return v;
  vec3 lo = min(floor(u), max(last - 1.0, vec3(0.0)));
  v.lo = uvec3(lo);
  v.hi = uvec3(min(lo + 1.0, last));
  v.t = u - lo;
  v.inside = true;
  return v;
}

float grid_sample(vec4 params[PRISMOID_FIELD_MAX_PARAMS], uvec3 s) {
  uvec2 n = uvec2(params[2].xy);
  return grid_values[(s.z * n.y + s.y) * n.x + s.x];
}

// The voxel's 8 samples, c[i + 2 j + 4 k] at corner (i, j, k).
void grid_corners(vec4 params[PRISMOID_FIELD_MAX_PARAMS], GridVoxel v, out float c[8]) {
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        c[i + 2 * j + 4 * k] = grid_sample(params, uvec3(i == 1 ? v.hi.x : v.lo.x, j == 1 ? v.hi.y : v.lo.y, k == 1 ? v.hi.z : v.lo.z));
}

float grid_lerp(float a, float b, float t) { return a + t * (b - a); }

float grid_field(vec4 params[PRISMOID_FIELD_MAX_PARAMS], vec3 p) {
  GridVoxel v = grid_locate(params, p);
  if (!v.inside) return params[0].w;
  float c[8];
  grid_corners(params, v, c);
  float x00 = grid_lerp(c[0], c[1], v.t.x), x10 = grid_lerp(c[2], c[3], v.t.x);
  float x01 = grid_lerp(c[4], c[5], v.t.x), x11 = grid_lerp(c[6], c[7], v.t.x);
  return grid_lerp(grid_lerp(x00, x10, v.t.y), grid_lerp(x01, x11, v.t.y), v.t.z);
}

vec3 grid_gradient(vec4 params[PRISMOID_FIELD_MAX_PARAMS], vec3 p) {
  GridVoxel v = grid_locate(params, p);
  if (!v.inside) return vec3(0.0);
  float c[8];
  grid_corners(params, v, c);
  vec3 t = v.t;
  float dx = grid_lerp(grid_lerp(c[1] - c[0], c[3] - c[2], t.y), grid_lerp(c[5] - c[4], c[7] - c[6], t.y), t.z);
  float dy = grid_lerp(grid_lerp(c[2] - c[0], c[3] - c[1], t.x), grid_lerp(c[6] - c[4], c[7] - c[5], t.x), t.z);
  float dz = grid_lerp(grid_lerp(c[4] - c[0], c[5] - c[1], t.x), grid_lerp(c[6] - c[2], c[7] - c[3], t.x), t.y);
  return vec3(dx, dy, dz) * params[1].xyz;
}

#endif
