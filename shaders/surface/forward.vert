#version 460
// The forward shading pass: the pre-pass's position (same expression, invariant) and the
// attributes the fragment shader shades with.
#extension GL_GOOGLE_include_directive : require
#include "transform.glsl"

layout(location = PRISMOID_SURFACE_VERTEX_POSITION) in vec3 in_position;
layout(location = PRISMOID_SURFACE_VERTEX_NORMAL) in vec3 in_normal;
layout(location = PRISMOID_SURFACE_VERTEX_COLOR) in vec3 in_color;

layout(location = 0) out vec3 v_position;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_color;

void main() {
  gl_Position = surface_clip_position(in_position);
  v_position = in_position;
  v_normal = in_normal;
  v_color = in_color;
}
