// Emission-absorption along one segment, integrated piece by piece of the transfer function:
// the float twin of volume::integrate_segment (renderer/volume/segment_integral.cpp), which
// documents the model and the method.
#ifndef PRISMOID_SEGMENT_INTEGRAL_GLSL
#define PRISMOID_SEGMENT_INTEGRAL_GLSL

const float kGaussNodes[4] = float[4](0.1834346425, 0.5255324099, 0.7966664774, 0.9602898565);
const float kGaussWeights[4] = float[4](0.3626837834, 0.3137066459, 0.2223810345, 0.1012285363);

float gauss_exp(float s0, float k, float a, float b) {
  float mid = 0.5 * (a + b), half_width = 0.5 * (b - a), sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    float t0 = mid - half_width * kGaussNodes[i], t1 = mid + half_width * kGaussNodes[i];
    sum += kGaussWeights[i] * (exp(-(s0 * t0 + k * t0 * t0)) + exp(-(s0 * t1 + k * t1 * t1)));
  }
  return sum * half_width;
}

// integral_0^h exp(-(s0 t + k t^2)) dt on sub-pieces where tau grows by 1/2; past tau = 17
// (e^-17 < 2^-24) the rest is one piece.
float integral_of_transmittance(float s0, float k, float h) {
  float tau_h = s0 * h + k * h * h;
  if (!(tau_h > 0.0)) return h;
  int steps = int(min(ceil(tau_h / 0.5), 34.0));
  float sum = 0.0, t_prev = 0.0;
  for (int i = 1; i <= steps; ++i) {
    float t = h;
    if (i < steps) {
      float y = 0.5 * float(i);
      t = clamp(2.0 * y / (s0 + sqrt(max(s0 * s0 + 4.0 * k * y, 0.0))), t_prev, h);
    }
    sum += gauss_exp(s0, k, t_prev, t);
    t_prev = t;
  }
  return sum;
}

// (premultiplied colour, alpha) of a piece of length h with linear sigma and colour.
vec4 integrate_piece(float h, float sigma0, float sigma1, vec3 c0, vec3 c1) {
  if (!(h > 0.0)) return vec4(0.0);
  float k = 0.5 * (sigma1 - sigma0) / h;
  float transmittance = exp(-0.5 * (sigma0 + sigma1) * h);
  float mean_transmittance = integral_of_transmittance(sigma0, k, h) / h;
  return vec4(c0 - c1 * transmittance + (c1 - c0) * mean_transmittance, 1.0 - transmittance);
}

vec4 composite_under(vec4 front, vec4 behind) { return front + (1.0 - front.a) * behind; }

#endif
