#version 460
// Emission-absorption of one cell's segment along the pixel ray (beyond the paper): the
// normalized scalar at the front and back of the interval comes from the cell's linear field;
// the segment's premultiplied colour and opacity come either from exact integration piece by
// piece of the transfer function, or from the pre-integrated table (a quality setting). The
// blend state composites front to back ("under"): dst += (1 - dst.a) * src.
#extension GL_EXT_mesh_shader : require
#extension GL_GOOGLE_include_directive : require
#include "../shared/volume.h"
#include "segment_integral.glsl"

layout(set = 0, binding = PRISMOID_BINDING_FRAME) uniform FrameBlock { FrameUniforms frame; };
layout(std430, set = 0, binding = PRISMOID_BINDING_PREINTEGRATED) readonly buffer Table { vec4 texels[]; };
layout(std430, set = 0, binding = PRISMOID_BINDING_TRANSFER) readonly buffer Transfer { vec4 tf_samples[]; };

layout(location = 0) in vec2 v_inv_depth;
layout(location = 2) in vec4 v_relative;
layout(location = 1) perprimitiveEXT flat in vec4 p_reference;  // w: the normalized scalar at the cell's reference point
layout(location = 0) out vec4 out_color;

#include "interval_ray.glsl"
#include "transfer_lookup.glsl"

vec4 texel(uint i, uint j, uint k, uint n) { return texels[(k * n + j) * n + i]; }

// Trilinear lookup at (x_front, x_back, length), each clamped into the table's range; the
// CPU twin is volume::lookup().
vec4 preintegrated(float x_front, float x_back, float len) {
  uint n = uint(frame.transfer.w);
  float scale = float(n - 1u);
  vec3 c = vec3(clamp(x_front, 0.0, 1.0), clamp(x_back, 0.0, 1.0), clamp(len / frame.transfer.z, 0.0, 1.0)) * scale;
  uvec3 b = min(uvec3(c), uvec3(n - 2u));
  vec3 f = c - vec3(b);
  vec4 c00 = mix(texel(b.x, b.y, b.z, n), texel(b.x + 1u, b.y, b.z, n), f.x);
  vec4 c10 = mix(texel(b.x, b.y + 1u, b.z, n), texel(b.x + 1u, b.y + 1u, b.z, n), f.x);
  vec4 c01 = mix(texel(b.x, b.y, b.z + 1u, n), texel(b.x + 1u, b.y, b.z + 1u, n), f.x);
  vec4 c11 = mix(texel(b.x, b.y + 1u, b.z + 1u, n), texel(b.x + 1u, b.y + 1u, b.z + 1u, n), f.x);
  return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

// The twin of volume::integrate_segment: pieces end where x crosses a sample.
vec4 exact_segment(float x_front, float x_back, float len) {
  uint n = frame.options.x;
  float dx = x_back - x_front;
  vec4 total = vec4(0.0);
  vec4 a = tf_at(x_front);
  float u_prev = 0.0;
  if (dx != 0.0) {
    for (uint s = 0u; s < n; ++s) {
      uint i = dx > 0.0 ? s : n - 1u - s;  // samples in the order the segment meets them
      float u = (tf_samples[2u * i].x - x_front) / dx;
      if (u > u_prev && u < 1.0) {
        vec4 b = tf_sample(i);
        total = composite_under(total, integrate_piece((u - u_prev) * len, a.w, b.w, a.rgb, b.rgb));
        a = b;
        u_prev = u;
      }
    }
  }
  vec4 b = tf_at(x_back);
  return composite_under(total, integrate_piece((1.0 - u_prev) * len, a.w, b.w, a.rgb, b.rgb));
}

void main() {
  IntervalRay r = interval_ray(v_inv_depth, v_relative, p_reference);
  float len = interval_length(r);
  // A non-finite interval (cannot happen for proxies that pass the area test) adds nothing.
  if (!(len > 0.0) || isinf(len)) {
    out_color = vec4(0.0);
    return;
  }
  out_color = frame.options.y == PRISMOID_SEGMENTS_TABLE ? preintegrated(r.field_front, r.field_back, len)
                                                         : exact_segment(r.field_front, r.field_back, len);
}
