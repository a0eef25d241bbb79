#version 460
// Adds sigma * (length of the pixel ray inside the tetrahedron) to the optical-depth target.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };

layout(location = 0) in vec2 v_inv_depth;
layout(location = 1) perprimitiveEXT flat in vec4 p_field;  // sigma(p) = dot(xyz, p) + w, camera space
layout(location = 0) out float out_optical_depth;

void main() {
  // Depths along the viewing axis of the two bounding surfaces at this pixel.
  float depth_a = 1.0 / v_inv_depth.x;
  float depth_b = 1.0 / v_inv_depth.y;
  // The pixel ray in camera space has direction (ndc.x / P00, ndc.y / P11, -1); one unit of
  // depth along it is |direction| units of length.
  vec2 ndc = gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0;
  vec2 slope = ndc * frame.ray_scale.xy;
  vec3 ray = vec3(slope, -1.0);  // the camera-space point at depth d on this pixel's ray is d * ray
  float length_per_depth = length(ray);
  // sigma is linear along the segment, so its integral is the length times its mean, the
  // mean of its values at the two ends.
  float mean_sigma = 0.5 * (depth_a + depth_b) * dot(p_field.xyz, ray) + p_field.w;
  out_optical_depth = max(mean_sigma, 0.0) * abs(depth_b - depth_a) * length_per_depth;
}
