#version 460
// The closest opaque triangle of a surface pass's ray: its global triangle index (the mesh's
// first triangle + the primitive within the mesh's BLAS, whose instance custom index is the
// mesh) and barycentrics.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "../../shared/surface.h"

layout(std430, set = 0, binding = PRISMOID_SURFACE_BINDING_MESHES) readonly buffer MeshBuffer { SurfaceMeshGpu scene_meshes[]; };
layout(location = PRISMOID_SURFACE_PAYLOAD_HIT) rayPayloadInEXT SurfaceHitPayload payload;
hitAttributeEXT vec2 barycentrics;

void main() {
  const uint triangle = scene_meshes[gl_InstanceCustomIndexEXT].info.x + uint(gl_PrimitiveID);
  payload.hit = vec4(gl_HitTEXT, barycentrics.x, barycentrics.y, 0.0);
  payload.id = uvec4(triangle, 1u, 0u, 0u);
}
