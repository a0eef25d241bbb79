#version 460
// forward.frag that also counts its invocations per pixel (tests of the depth pre-pass).
#extension GL_GOOGLE_include_directive : require
#define PRISMOID_COUNT_SHADING
#include "forward_frag.glsl"
