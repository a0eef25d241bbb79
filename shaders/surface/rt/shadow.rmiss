#version 460
// Shadow rays of the surface passes: reached only when nothing lies on the segment.
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "../../shared/surface.h"

layout(location = PRISMOID_SURFACE_PAYLOAD_SHADOW) rayPayloadInEXT uint shadow_visible;

void main() { shadow_visible = 1u; }
