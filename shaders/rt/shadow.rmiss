#version 460
#extension GL_EXT_ray_tracing : require
#extension GL_GOOGLE_include_directive : require
#include "shared/rt.h"

layout(location = PRISMOID_RT_PAYLOAD_VISIBLE) rayPayloadInEXT uint visible;

void main() { visible = 1u; }
