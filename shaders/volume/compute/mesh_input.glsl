// What the compute backend's per-cell kernels read: the frame, the mesh (volume.h's bindings,
// as the mesh shader reads them) and the pass's push constants, and one cell's corners with
// the field it integrates there (cell_field.glsl, the mesh shader's choice).
#ifndef PRISMOID_CI_MESH_INPUT_GLSL
#define PRISMOID_CI_MESH_INPUT_GLSL

#include "../mesh_bindings.glsl"
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
