// One cell's segment of emission-absorption, as every interval backend integrates it: exactly,
// piece by piece of the transfer function, or by lookup in the pre-integrated table (a quality
// setting). The caller declares `frame`, `tf_samples` (PRISMOID_BINDING_TRANSFER) and `texels`
// (PRISMOID_BINDING_PREINTEGRATED).
#ifndef PRISMOID_SEGMENT_EMISSION_GLSL
#define PRISMOID_SEGMENT_EMISSION_GLSL

#include "segment_integral.glsl"
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

// The segment of length `len` whose normalized scalar goes from x_front to x_back, as these
// frame settings integrate it.
vec4 segment_emission(float x_front, float x_back, float len) {
  return frame.options.y == PRISMOID_SEGMENTS_TABLE ? preintegrated(x_front, x_back, len) : exact_segment(x_front, x_back, len);
}

#endif
