// The frame and the mesh as both interval backends read them (volume.h's bindings): the mesh
// shader (interval_body.glsl) and the compute backend's kernels (compute/mesh_input.glsl).
#ifndef PRISMOID_MESH_BINDINGS_GLSL
#define PRISMOID_MESH_BINDINGS_GLSL

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };
layout(std430, set = 0, binding = PRISMOID_BINDING_POSITIONS) readonly buffer Positions { vec4 positions[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TETS) readonly buffer Tets { uvec4 tets[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_CELL_SIGMA) readonly buffer CellSigma { float cell_sigma[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_POINT_SIGMA) readonly buffer PointSigma { float point_sigma[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_CELL_SCALAR) readonly buffer CellScalar { float cell_scalar[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_POINT_SCALAR) readonly buffer PointScalar { float point_scalar[]; };

#endif
