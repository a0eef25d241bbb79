// Layouts shared by the interval-shading shaders and renderer/volume.
#ifndef PRISMOID_SHARED_VOLUME_H
#define PRISMOID_SHARED_VOLUME_H
#include "common.h"

PRISMOID_SHARED_BEGIN

// Descriptor bindings of set 0 of the interval-shading pipeline.
#define PRISMOID_BINDING_FRAME 0      // uniform FrameUniforms
#define PRISMOID_BINDING_POSITIONS 1  // readonly vec4[]: xyz relative to the mesh origin
#define PRISMOID_BINDING_TETS 2       // readonly uvec4[]: four point indices per cell
#define PRISMOID_BINDING_CELL_SIGMA 3 // readonly float[]: extinction per cell (1/length)
#define PRISMOID_BINDING_POINT_SIGMA 4 // readonly float[]: extinction per point (linear fields)

// Tetrahedra handled by one mesh-shader workgroup, one per invocation. A near-clipped cell
// emits up to 15 vertices, and 256 output vertices is the common limit (lavapipe, NVIDIA).
#define PRISMOID_TETS_PER_WORKGROUP 16
// A tetrahedron's proxy: at most 5 vertices and 4 triangles (case 2 of the projection).
#define PRISMOID_PROXY_MAX_VERTICES 5
#define PRISMOID_PROXY_MAX_TRIANGLES 4
// A near-clipped cell becomes up to 3 pieces, each with its own proxy; a workgroup declares
// room for all of its cells' pieces.
#define PRISMOID_WORKGROUP_MAX_VERTICES (PRISMOID_TETS_PER_WORKGROUP * 3 * PRISMOID_PROXY_MAX_VERTICES)
#define PRISMOID_WORKGROUP_MAX_TRIANGLES (PRISMOID_TETS_PER_WORKGROUP * 3 * PRISMOID_PROXY_MAX_TRIANGLES)

struct FrameUniforms {
  mat4 view;        // mesh-local coordinates -> camera space (camera looks along -z)
  mat4 projection;  // camera space -> clip space (Vulkan: y down, depth 0..1)
  vec4 viewport;    // width, height, 1/width, 1/height
  vec4 ray_scale;   // 1/P[0][0], 1/P[1][1], near distance (cells are clipped there), unused
  uvec4 counts;     // x: tetrahedron count, y: 1 when sigma is linear per cell (point values)
};

// Push constants of the resolve pass (optical depth -> display colour).
#define PRISMOID_QUANTITY_OPTICAL_DEPTH 0u
#define PRISMOID_QUANTITY_TRANSMITTANCE 1u
struct ResolvePush {
  vec4 background;    // display colour where nothing absorbs
  vec4 medium;        // colour the medium tends to where it is opaque
  uvec4 params;       // x: quantity, y: width, z: height, w: unused
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::FrameUniforms) == 176);
static_assert(offsetof(prismoid::gpu::FrameUniforms, viewport) == 128);
static_assert(offsetof(prismoid::gpu::FrameUniforms, counts) == 160);
static_assert(sizeof(prismoid::gpu::ResolvePush) == 48);
#endif

#endif
