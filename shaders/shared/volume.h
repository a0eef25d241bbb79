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
#define PRISMOID_BINDING_CELL_SCALAR 5  // readonly float[]: transfer-function scalar per cell
#define PRISMOID_BINDING_POINT_SCALAR 6 // readonly float[]: transfer-function scalar per point
#define PRISMOID_BINDING_ORDER 7        // readonly uint[]: cells in drawing order (front to back)
#define PRISMOID_BINDING_PREINTEGRATED 8 // readonly vec4[]: pre-integrated (colour, alpha) table
#define PRISMOID_BINDING_TRANSFER 9     // readonly vec4[]: transfer-function samples, 2 per sample:
                                        // (x, sigma, 0, 0), (r, g, b, 0), sorted by x
#define PRISMOID_BINDING_TETLETS 10      // readonly uvec4[]: per tetlet: first point, points, first cell, cells
#define PRISMOID_BINDING_TETLET_POINTS 11 // readonly uint[]: each tetlet's points (global indices)
#define PRISMOID_BINDING_TETLET_CELLS 12  // readonly uvec2[]: cell index, its 4 corners as 8-bit tetlet-local indices
#define PRISMOID_TETLET_MAX_POINTS 64     // shared-memory points per tetlet
#define PRISMOID_BINDING_FIELD_GRID 13    // readonly float[]: a sampled grid's values, x fastest (PRISMOID_FIELD_GRID)
// readonly float[] per pixel, row 0 at the top: the depth along the viewing axis where its ray ends
// (opaque geometry; +inf: nowhere), read when FrameUniforms.options.z is 1. The compute backend's
// set has it at the same binding (after its own, compute_intervals.h).
#define PRISMOID_BINDING_DEPTH_LIMIT 27

// How a segment's emission is integrated (FrameUniforms.options.y).
#define PRISMOID_SEGMENTS_EXACT 0u   // in the fragment shader, piece by piece of the transfer function
#define PRISMOID_SEGMENTS_TABLE 1u   // trilinear lookup in the pre-integrated table

// What the interval pass integrates (FrameUniforms.counts.z).
#define PRISMOID_INTEGRAND_OPTICAL_DEPTH 0u  // sigma * length, additive: order independent
#define PRISMOID_INTEGRAND_EMISSION 1u       // transfer-function emission-absorption, composited in order

// Tetrahedra handled by one mesh-shader workgroup, one per invocation: 1, 4, 8 or 16 (one
// shader variant each; the default is 16). A near-clipped cell emits up to 15 vertices, and
// 256 output vertices is the common limit (lavapipe, NVIDIA).
#define PRISMOID_MAX_TETS_PER_WORKGROUP 16
#ifndef PRISMOID_TETS_PER_WORKGROUP
#define PRISMOID_TETS_PER_WORKGROUP PRISMOID_MAX_TETS_PER_WORKGROUP
#endif
// A tetrahedron's proxy: at most 5 vertices and 4 triangles (case 2 of the projection).
#define PRISMOID_PROXY_MAX_VERTICES 5
#define PRISMOID_PROXY_MAX_TRIANGLES 4
// A near-clipped cell becomes up to 3 pieces, each with its own proxy; a workgroup declares
// room for all of its cells' pieces.
#define PRISMOID_WORKGROUP_MAX_VERTICES (PRISMOID_TETS_PER_WORKGROUP * 3 * PRISMOID_PROXY_MAX_VERTICES)
#define PRISMOID_WORKGROUP_MAX_TRIANGLES (PRISMOID_TETS_PER_WORKGROUP * 3 * PRISMOID_PROXY_MAX_TRIANGLES)
#define PRISMOID_CELL_MAX_VERTICES (3 * PRISMOID_PROXY_MAX_VERTICES)    // a near-clipped cell's proxies
#define PRISMOID_CELL_MAX_TRIANGLES (3 * PRISMOID_PROXY_MAX_TRIANGLES)

// Analytic fields, evaluated in world coordinates identically by renderer/volume/analytic_field
// (double) and shaders/volume/analytic_field.glsl (float).
#define PRISMOID_FIELD_LINEAR 0u          // dot(params[0].xyz, p) + params[0].w
#define PRISMOID_FIELD_MARSCHNER_LOBB 1u  // params[0] = (f_M, alpha, 0, 0), on [-1, 1]^3
#define PRISMOID_FIELD_GAUSSIAN_BLOBS 2u  // params[i] = (centre, width): sum of exp(-|p-c|^2 / (2 width^2))
// Trilinear interpolation of PRISMOID_BINDING_FIELD_GRID (renderer/volume/sampled_grid):
// params[0] = (sample (0,0,0), background), params[1] = (1 / spacing, 0), params[2] = (dims, 0).
#define PRISMOID_FIELD_GRID 3u
#define PRISMOID_FIELD_MAX_PARAMS 4

// What march.frag computes along its interval (FrameUniforms.field.z).
#define PRISMOID_MARCH_OPTICAL_DEPTH 0u  // integral of density_scale * field, additive
#define PRISMOID_MARCH_COLOR 1u          // transfer function of the field, composited front to back
#define PRISMOID_MARCH_ISOSURFACE 2u     // first point with field >= isovalue, depth tested
// Most steps one fragment takes (a bound on its cost; the renderer refuses step settings
// that would need more in the longest cell).
#define PRISMOID_MARCH_MAX_STEPS 4096u
// Isosurface shading: ambient + (1 - ambient) * |cos| of the angle between normal and view ray.
#define PRISMOID_ISOSURFACE_AMBIENT 0.15

struct FrameUniforms {
  mat4 view;        // mesh-local coordinates -> camera space (camera looks along -z)
  mat4 projection;  // camera space -> clip space (Vulkan: y down, depth 0..1)
  vec4 viewport;    // width, height, 1/width, 1/height
  vec4 ray_scale;   // 1/P[0][0], 1/P[1][1], near distance (cells are clipped there), near distance
                    // minus the depth of the mesh origin (mesh-local 0)
  uvec4 counts;     // x: tetrahedron count, y: 1 when the field is linear per cell (point values),
                    // z: PRISMOID_INTEGRAND_*, w: 1 when cells are drawn in the order of PRISMOID_BINDING_ORDER
  vec4 transfer;    // x, y: the transfer function's x = scalar * x + y (volume::scalar_mapping),
                    // z: table's longest length, w: table size per axis (texels)
  uvec4 options;    // x: transfer-function sample count, y: PRISMOID_SEGMENTS_*, z: 1 when rays end at PRISMOID_BINDING_DEPTH_LIMIT
  // Marching inside intervals (march.frag): an analytic field in its own coordinates.
  mat4 camera_to_mesh;  // inverse of `view`: camera space -> mesh-local coordinates
  // xyz: the field's coordinates of mesh-local 0, w: the field's length of one mesh-local unit
  // (field point = field_origin.xyz + field_origin.w * local). (0, 1) when the field's
  // parameters are uploaded moved and scaled into the mesh frame (in double: volume::placed),
  // so a field far from the world origin or of any size keeps float precision.
  vec4 field_origin;
  vec4 march;           // x: largest step (mesh-local length), y: isovalue, z: density scale, w: the
                        // largest extinction a sample may have (volume::extinction_cap)
  uvec4 field;          // x: PRISMOID_FIELD_*, y: parameter count, z: PRISMOID_MARCH_*, w: unused
  vec4 field_params[PRISMOID_FIELD_MAX_PARAMS];  // per field kind, see analytic_field.glsl
};

// Push constants of the resolve pass (optical depth -> display colour).
#define PRISMOID_QUANTITY_OPTICAL_DEPTH 0u
#define PRISMOID_QUANTITY_TRANSMITTANCE 1u
#define PRISMOID_QUANTITY_COLOR 2u  // emission-absorption: display = colour over the background
#define PRISMOID_QUANTITY_ISOSURFACE 3u  // emission target holds (shaded rgb, distance to the hit; 0: none)
struct ResolvePush {
  vec4 background;    // display colour where nothing absorbs
  vec4 medium;        // colour the medium tends to where it is opaque
  uvec4 params;       // x: quantity, y: width, z: height, w: unused
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::FrameUniforms) == 384);
static_assert(offsetof(prismoid::gpu::FrameUniforms, camera_to_mesh) == 208);
static_assert(offsetof(prismoid::gpu::FrameUniforms, field_origin) == 272);
static_assert(offsetof(prismoid::gpu::FrameUniforms, march) == 288);
static_assert(offsetof(prismoid::gpu::FrameUniforms, field) == 304);
static_assert(offsetof(prismoid::gpu::FrameUniforms, field_params) == 320);
static_assert(offsetof(prismoid::gpu::FrameUniforms, transfer) == 176);
static_assert(offsetof(prismoid::gpu::FrameUniforms, viewport) == 128);
static_assert(offsetof(prismoid::gpu::FrameUniforms, counts) == 160);
static_assert(sizeof(prismoid::gpu::ResolvePush) == 48);
#endif

#endif
