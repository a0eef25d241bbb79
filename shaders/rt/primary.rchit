#version 460
// The closest opaque triangle: its mesh (the instance's custom index), triangle and barycentrics.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "shared/rt.h"

layout(location = PRISMOID_RT_PAYLOAD_HIT) rayPayloadInEXT RayHitRecord payload;
hitAttributeEXT vec2 barycentrics;

void main() {
  payload.hit = vec4(gl_HitTEXT, barycentrics.x, barycentrics.y, 0.0);
  payload.id = uvec4(uint(gl_InstanceCustomIndexEXT), uint(gl_PrimitiveID), 1u, 0u);
}
