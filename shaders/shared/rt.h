// Layouts shared by the ray caster's shaders (shaders/rt/) and renderer/rt/ray_caster.cpp.
// Coordinates on the GPU are floats relative to the scene's origin (SceneAccel::origin()).
#ifndef PRISMOID_SHARED_RT_H
#define PRISMOID_SHARED_RT_H
#include "common.h"

PRISMOID_SHARED_BEGIN

// Descriptor bindings of set 0 of the ray caster's pipeline.
#define PRISMOID_RT_BINDING_TLAS 0         // accelerationStructureEXT: the scene
#define PRISMOID_RT_BINDING_HITS 1         // writeonly RayHitRecord[]: one per pixel, row-major
#define PRISMOID_RT_BINDING_SHADOW_RAYS 2  // readonly ShadowRayRecord[]
#define PRISMOID_RT_BINDING_VISIBILITY 3   // writeonly uint[]: 1 where a shadow ray reaches its end

// Shader groups of the ray caster's pipeline, by their index in each region of the table.
#define PRISMOID_RT_RAYGEN_PRIMARY 0
#define PRISMOID_RT_RAYGEN_SHADOW 1
#define PRISMOID_RT_MISS_PRIMARY 0
#define PRISMOID_RT_MISS_SHADOW 1

// Payload locations.
#define PRISMOID_RT_PAYLOAD_HIT 0
#define PRISMOID_RT_PAYLOAD_VISIBLE 1

// A primary ray through the centre of pixel (x, y) runs from `eye` along
// normalize(forward + ndc_x * right - ndc_y * up), ndc = 2 (pixel + 0.5) / size - 1, starting
// where it crosses the near plane (t = near / dot(direction, forward)): the convention of the
// CPU reference's ray_direction (renderer/reference/tet_ray.hpp).
struct RayCastPush {
  vec4 eye;      // xyz: camera position relative to the scene origin, w: near distance
  vec4 forward;  // xyz: unit view direction
  vec4 right;    // xyz: unit right vector * tan(fovy / 2) * aspect
  vec4 up;       // xyz: unit up vector * tan(fovy / 2)
  uvec4 size;    // x: width, y: height (primary); z: ray count, w: launch width (shadow)
};

struct RayHitRecord {
  vec4 hit;  // x: ray parameter t of the hit along the unit direction (-1 on a miss), y, z: barycentric
             // weights of the triangle's second and third vertex, w: 0
  uvec4 id;  // x: mesh index, y: triangle index within the mesh, z: 1 for a hit, 0 for a miss, w: 0
};

// A segment origin + t direction for t in [t_min, t_max]: visible when nothing lies on it.
struct ShadowRayRecord {
  vec4 origin;     // xyz relative to the scene origin, w: t_min
  vec4 direction;  // xyz (any length), w: t_max
};

PRISMOID_SHARED_END

#endif
