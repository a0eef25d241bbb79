// What the compute backend's per-cell kernels read: the frame, the mesh (volume.h's bindings,
// as the mesh shader reads them) and the pass's push constants, and one cell's corners with
// the field it integrates there (cell_field.glsl, the mesh shader's choice).
#ifndef PRISMOID_CI_MESH_INPUT_GLSL
#define PRISMOID_CI_MESH_INPUT_GLSL

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };
layout(std430, set = 0, binding = PRISMOID_BINDING_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TETS) readonly buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_CELL_SIGMA) readonly buffer CellSigma { float cell_sigma[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_POINT_SIGMA) readonly buffer PointSigma { float point_sigma[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_CELL_SCALAR) readonly buffer CellScalar { float cell_scalar[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_POINT_SCALAR) readonly buffer PointScalar { float point_scalar[]; };
layout(push_constant) uniform Push { ComputeIntervalsPush push; };

#include "../cell_field.glsl"

struct CellInput {
  uvec4 points;       // the corners' point indices
  vec3 position[4];   // mesh-local
  float field[4];     // the integrated field at the corners
  bool drawn;         // false: adds nothing (no extinction in an optical-depth frame)
};

CellInput load_cell(uint cell) {
  CellInput c;
  c.points = tets[cell];
  bool emission = frame.counts.z == PRISMOID_INTEGRAND_EMISSION;
  bool per_point = frame.counts.y != 0u;
  float value[4];
  for (int i = 0; i < 4; ++i) {
    c.position[i] = positions[c.points[i]].xyz;
    value[i] = per_point ? (emission ? point_scalar[c.points[i]] : point_sigma[c.points[i]]) : 0.0;
  }
  c.drawn = cell_field(cell, emission, per_point, value, c.field) > 0.0;
  return c;
}

#endif
