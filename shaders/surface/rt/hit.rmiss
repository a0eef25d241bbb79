#version 460
// Rays of the surface passes that look for the closest surface: nothing was hit.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "../../shared/surface.h"

layout(location = PRISMOID_SURFACE_PAYLOAD_HIT) rayPayloadInEXT SurfaceHitPayload payload;

void main() {
  payload.hit = vec4(-1.0, 0.0, 0.0, 0.0);
  payload.id = uvec4(0u);
}
