// The transfer function as the fragment shaders read it: PRISMOID_BINDING_TRANSFER holds its
// breakpoints (volume::breakpoints), two vec4 per sample; the caller declares `tf_samples`
// and `frame`. The float twin of volume::evaluate.
#ifndef PRISMOID_TRANSFER_LOOKUP_GLSL
#define PRISMOID_TRANSFER_LOOKUP_GLSL

// (rgb, sigma) of sample i, and of the transfer function at x (clamped into [0, 1]).
vec4 tf_sample(uint i) { return vec4(tf_samples[2u * i + 1u].rgb, tf_samples[2u * i].y); }
vec4 tf_at(float x) {
  uint n = frame.options.x;
  x = clamp(x, 0.0, 1.0);
  for (uint i = 1u; i < n; ++i) {
    float x1 = tf_samples[2u * i].x;
    if (x <= x1) {
      float x0 = tf_samples[2u * (i - 1u)].x;
      float w = x1 > x0 ? (x - x0) / (x1 - x0) : 1.0;
      return mix(tf_sample(i - 1u), tf_sample(i), w);
    }
  }
  return tf_sample(n - 1u);
}

#endif
