#version 460
// The depth pre-pass: positions only.
#extension GL_GOOGLE_include_directive : require
#include "transform.glsl"

layout(location = PRISMOID_SURFACE_VERTEX_POSITION) in vec3 in_position;

void main() { gl_Position = surface_clip_position(in_position); }
