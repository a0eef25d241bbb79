// Layouts shared by the surface shaders (shaders/surface/) and renderer/surface: materials,
// lights and the per-frame block every surface backend shades with. All positions are float
// and relative to the scene's origin (GpuSurfaceScene::origin, kept in double), so a scene far
// from the world origin keeps its precision.
#ifndef PRISMOID_SHARED_SURFACE_H
#define PRISMOID_SHARED_SURFACE_H
#include "common.h"

PRISMOID_SHARED_BEGIN

// Descriptor bindings of set 0, shared by every surface backend's shading.
#define PRISMOID_SURFACE_BINDING_FRAME 0              // uniform SurfaceFrame
#define PRISMOID_SURFACE_BINDING_MATERIALS 1          // readonly SurfaceMaterialGpu[]
#define PRISMOID_SURFACE_BINDING_TRIANGLES 2          // readonly SurfaceTriangleGpu[], by gl_PrimitiveID
#define PRISMOID_SURFACE_BINDING_POINT_LIGHTS 3       // readonly PointLightGpu[]
#define PRISMOID_SURFACE_BINDING_DIRECTIONAL_LIGHTS 4 // readonly DirectionalLightGpu[]
#define PRISMOID_SURFACE_BINDING_EMITTERS 5           // readonly EmitterGpu[]: emissive triangles
#define PRISMOID_SURFACE_BINDING_SHADE_COUNT 6        // r32ui storage image: shading invocations per pixel
                                                      // (forward_counted.frag only)
// Bindings of passes that rebuild surface points from (triangle, barycentrics) rather than from
// rasterized vertex attributes (shaders/surface/surface_point.glsl; define
// PRISMOID_SURFACE_VERTEX_BUFFERS before including scene_bindings.glsl), and of ray-traced passes.
#define PRISMOID_SURFACE_BINDING_TLAS 7               // accelerationStructureEXT: the scene (renderer/rt SceneAccel)
#define PRISMOID_SURFACE_BINDING_POSITIONS 8          // readonly float[]: 3 per vertex (the vertex buffer)
#define PRISMOID_SURFACE_BINDING_ATTRIBUTES 9         // readonly float[]: normal xyz, colour rgb per vertex
#define PRISMOID_SURFACE_BINDING_INDICES 10           // readonly uint[]: 3 per global triangle
#define PRISMOID_SURFACE_BINDING_MESHES 11            // readonly SurfaceMeshGpu[]: per mesh

// Ray-tracing pipelines of the surface passes (shaders/surface/rt/): every such pipeline lists
// the miss shaders and the hit group in this order, so shadow_rays.glsl and bounce rays can
// name them by index.
#define PRISMOID_SURFACE_MISS_SHADOW 0    // surface/rt/shadow.rmiss: sets the visibility payload to 1
#define PRISMOID_SURFACE_MISS_HIT 1       // surface/rt/hit.rmiss: leaves SurfaceHitPayload as a miss
#define PRISMOID_SURFACE_HIT_GROUP 0      // surface/rt/hit.rchit: fills SurfaceHitPayload
#define PRISMOID_SURFACE_PAYLOAD_HIT 0    // rayPayloadEXT SurfaceHitPayload
#define PRISMOID_SURFACE_PAYLOAD_SHADOW 1 // rayPayloadEXT uint: 1 when the segment is free

// The first binding number a backend may use for its own resources in set 0.
#define PRISMOID_SURFACE_BINDING_BACKEND 16

// Vertex input of the raster backends: binding 0 holds positions (vec3, stride 12), binding 1
// the shading attributes (normal vec3, colour vec3; stride 24).
#define PRISMOID_SURFACE_VERTEX_POSITION 0
#define PRISMOID_SURFACE_VERTEX_NORMAL 1   // zero for a mesh without normals (flat shading)
#define PRISMOID_SURFACE_VERTEX_COLOR 2    // the mesh's per-vertex colour, else (1, 1, 1)

// Area lights (emissive triangles): the diffuse lobe is integrated in closed form (Lambert's
// formula for the polygon clipped to the horizons); the GGX lobe by a fixed rule: the clipped
// polygon's triangles are each cut into N^2 congruent sub-triangles and each sub-triangle
// contributes its exact solid angle times the integrand towards its centroid. The CPU
// reference (renderer/reference/direct_light.hpp) evaluates the same rule in double and, for
// comparison, the exact integral.
#define PRISMOID_AREA_SPECULAR_SUBDIVISION 4u
// A point closer to an emissive triangle's plane than this times the scene's scale (half the
// bounds' largest side, GpuSurfaceScene::scale) gets no light from it: it sees the emitter
// edge-on, up to rounding. Without the rule a point on an emitter's corner or edge (an Htex
// vertex texel on an emissive mesh, a bounce hit beside a neighbouring emitter) meets the
// closed form's singular case, a corner vector of length zero, where float rounding decides;
// the GPU machine's float there gave samples 0.7% above the furnace's closed form. The CPU
// reference applies the same rule.
#define PRISMOID_EMITTER_PLANE_EPSILON (1.0 / 1048576.0)

// A triangle clipped by two planes has at most 5 corners.
#define PRISMOID_CLIPPED_POLYGON_MAX 5

// Shadow rays (shaders/surface/shadow_rays.glsl; its CPU double twin
// renderer/reference/shadow_rays.hpp follows the same rules):
//  - every shadow ray starts at the shading point moved off its surface along the viewer-side
//    geometric normal by PRISMOID_SHADOW_RAY_OFFSET times the scene's scale (SurfaceFrame
//    subpixel.z: the largest |coordinate| of any vertex relative to the scene origin);
//  - a point light's segment ends that same distance short of the light; an emitter's sample
//    point is moved off the emitter by it along the emitter's normal (towards its front);
//  - an emissive triangle's visibility is the ratio over its PRISMOID_EMITTER_SHADOW_SAMPLES
//    fixed points below (barycentric weights of corners 0, 1, 2: the centroids of the four
//    triangles of its midpoint subdivision), each weighted by
//    max(cos at the point with the shading normal, 0) max(cos at the emitter, 0) / d^2
//    (from the shading point to the sample point; 0 below the point's geometric horizon, which
//    the closed-form term clips away); 1 when every weight is 0.
// The offset is 2^-16 of the scale: at least 128 float ulps of any vertex coordinate, far above
// the few ulps by which a point interpolated from float corners lies off its triangle's plane
// and by which a float ray-triangle test can err, so that the surface a ray leaves (and its
// coplanar neighbours) is never found again; and small next to any feature the scene resolves.
#define PRISMOID_SHADOW_RAY_OFFSET 1.52587890625e-5
#define PRISMOID_EMITTER_SHADOW_SAMPLES 4u
#define PRISMOID_EMITTER_SHADOW_SAMPLE_0 (2.0 / 3.0), (1.0 / 6.0), (1.0 / 6.0)
#define PRISMOID_EMITTER_SHADOW_SAMPLE_1 (1.0 / 6.0), (2.0 / 3.0), (1.0 / 6.0)
#define PRISMOID_EMITTER_SHADOW_SAMPLE_2 (1.0 / 6.0), (1.0 / 6.0), (2.0 / 3.0)
#define PRISMOID_EMITTER_SHADOW_SAMPLE_3 (1.0 / 3.0), (1.0 / 3.0), (1.0 / 3.0)

// GGX alpha below this is raised to it (as kMinGgxAlpha in scene/surface_scene.hpp).
#define PRISMOID_MIN_GGX_ALPHA 1e-3

struct SurfaceMaterialGpu {
  vec4 albedo;    // rgb: diffuse albedo; w: GGX alpha = max(roughness^2, PRISMOID_MIN_GGX_ALPHA)
  vec4 specular;  // rgb: F0 at normal incidence; w: 1 when F0 is not zero (the GGX lobe is evaluated)
  vec4 emission;  // rgb: radiance leaving the front side; w: unused
};

struct SurfaceTriangleGpu {
  vec4 normal;  // xyz: unit winding normal (v1 - v0) x (v2 - v0); zero for a degenerate triangle
  vec4 color;   // rgb: the mesh's per-triangle colour, else (1, 1, 1)
  uvec4 info;   // x: material index, y: mesh index, z: triangle index within its mesh, w: unused
};

// A mesh of the scene: where its triangles start among all meshes' (global triangle index =
// first + the index within the mesh, e.g. gl_PrimitiveID of a hit in the mesh's BLAS, whose
// instance custom index is the mesh index).
struct SurfaceMeshGpu {
  uvec4 info;  // x: first global triangle, y: triangle count, z: first vertex, w: material index
};

// What a closest-hit shader reports: the hit's global triangle and barycentrics.
struct SurfaceHitPayload {
  vec4 hit;  // x: t along the traced direction (-1 on a miss), y, z: barycentric weights of corners 1 and 2
  uvec4 id;  // x: global triangle index, y: 1 for a hit, z, w: 0
};

struct PointLightGpu {
  vec4 position;   // xyz relative to the scene origin
  vec4 intensity;  // rgb radiant intensity (irradiance I cos / r^2)
};

struct DirectionalLightGpu {
  vec4 to_light;    // xyz: unit vector towards the light (against its direction of travel)
  vec4 irradiance;  // rgb irradiance on a surface facing the light
};

// One emissive triangle (non-degenerate, emission not zero).
struct EmitterGpu {
  vec4 v0, v1, v2;  // corners relative to the scene origin
  vec4 emission;    // rgb radiance from the front side; w: area
  vec4 normal;      // xyz: unit winding normal (the front side)
  uvec4 info;       // x: its global triangle index (a point on it does not light itself)
};

struct SurfaceFrame {
  mat4 view;            // scene-local coordinates -> camera space (camera looks along -z)
  mat4 projection;      // camera space -> clip space, with the sub-pixel offset folded in
  vec4 viewport;        // width, height, 1/width, 1/height
  vec4 eye;             // xyz: camera position relative to the scene origin
  uvec4 counts;         // x: point lights, y: directional lights, z: emitters, w: 1 when the sky is not black
  vec4 sky_top;         // rgb: Sky::top
  vec4 sky_bottom;      // rgb: Sky::bottom
  vec4 sky_up;          // xyz: unit Sky::up; w: 1 when ReSTIR GI carries the sky (no ambient term), else 0
  vec4 camera_right;    // xyz: unit right vector; w: tan(fovy / 2) * aspect
  vec4 camera_up;       // xyz: unit up vector (in the image); w: tan(fovy / 2)
  vec4 camera_forward;  // xyz: unit viewing direction
  vec4 subpixel;        // xy: where in the pixel the image is sampled, in pixels from its centre;
                        // z: the scene's scale for shadow-ray offsets (largest |vertex coordinate|
                        // relative to the origin; 0: unknown, shadow_rays.glsl then uses max(|p|, 1))
};

PRISMOID_SHARED_END

#ifdef __cplusplus
static_assert(sizeof(prismoid::gpu::SurfaceMaterialGpu) == 48);
static_assert(sizeof(prismoid::gpu::SurfaceTriangleGpu) == 48);
static_assert(sizeof(prismoid::gpu::SurfaceMeshGpu) == 16);
static_assert(sizeof(prismoid::gpu::SurfaceHitPayload) == 32);
static_assert(sizeof(prismoid::gpu::PointLightGpu) == 32);
static_assert(sizeof(prismoid::gpu::DirectionalLightGpu) == 32);
static_assert(sizeof(prismoid::gpu::EmitterGpu) == 96);
static_assert(offsetof(prismoid::gpu::EmitterGpu, info) == 80);
static_assert(offsetof(prismoid::gpu::SurfaceFrame, viewport) == 128);
static_assert(offsetof(prismoid::gpu::SurfaceFrame, counts) == 160);
static_assert(offsetof(prismoid::gpu::SurfaceFrame, subpixel) == 272);
static_assert(sizeof(prismoid::gpu::SurfaceFrame) == 288);
#endif

#endif
