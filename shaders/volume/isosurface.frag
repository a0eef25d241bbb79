#version 460
// Isosurface by marching inside intervals (isosurface_hit.glsl). Cells are drawn in any
// order: the depth test (greater, on near / depth) keeps the nearest hit per pixel.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };

#include "analytic_field.glsl"
#include "isosurface_hit.glsl"

layout(location = 0) in vec2 v_inv_depth;
layout(location = 2) in vec4 v_relative;
layout(location = 1) perprimitiveEXT flat in vec4 p_reference;
layout(location = 0) out vec4 out_hit;  // shaded rgb, distance from the eye to the hit (world)

void main() {
  IntervalRay r = interval_ray(v_inv_depth, v_relative, p_reference);
  float shade, hit_depth;
  if (!isosurface_hit(r, p_reference, shade, hit_depth)) discard;
  out_hit = vec4(vec3(shade), hit_depth * r.length_per_depth);
  gl_FragDepth = frame.ray_scale.z / hit_depth;  // near / depth: 1 at the near plane, smaller behind
}
