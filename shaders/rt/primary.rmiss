#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "shared/rt.h"

layout(location = PRISMOID_RT_PAYLOAD_HIT) rayPayloadInEXT RayHitRecord payload;

void main() {
  payload.hit = vec4(-1.0, 0.0, 0.0, 0.0);
  payload.id = uvec4(0u);
}
