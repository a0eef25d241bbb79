// Float functions that C++ and GLSL compile from the same text, so that the C++ tests can
// measure their error (tests/surface/test_area_light.cpp) and the GPU tolerances can rely on it.
// Only +, -, *, / and comparisons: Vulkan guarantees these (correctly rounded, division within
// 2.5 ulp), while its atan may be off by 4096 ulp.
#ifndef PRISMOID_SHARED_SURFACE_MATH_H
#define PRISMOID_SHARED_SURFACE_MATH_H
#include "common.h"

#ifdef __cplusplus
#define PRISMOID_INLINE inline
#else
#define PRISMOID_INLINE
#endif

PRISMOID_SHARED_BEGIN

// atan(t) for t in [0, 1]. Above tan(pi/12) = 2 - sqrt(3) the argument is reduced with
// atan(t) = pi/6 + atan((sqrt(3) t - 1) / (t + sqrt(3))), which maps (tan(pi/12), 1] into
// (-tan(pi/12), tan(pi/12)]; there the Taylor series up to u^13 leaves out at most
// |u|^15 / 15 < 1.8e-10.
PRISMOID_INLINE float prismoid_atan_unit(float t) {
  const float sqrt3 = 1.7320508f;
  const bool reduce = t > 0.26794919f;
  const float u = reduce ? (sqrt3 * t - 1.0f) / (t + sqrt3) : t;
  const float u2 = u * u;
  const float series =
      u * (1.0f + u2 * (-0.33333333f + u2 * (0.2f + u2 * (-0.14285714f + u2 * (0.11111111f + u2 * (-0.09090909f + u2 * 0.07692308f))))));
  return reduce ? 0.52359878f + series : series;
}

// atan2(y, x) for y >= 0 (the angle in [0, pi] of the vector (x, y)); 0 for (0, 0).
PRISMOID_INLINE float prismoid_atan2_upper(float y, float x) {
  const float ax = x < 0.0f ? -x : x;
  const float lo = y < ax ? y : ax;
  const float hi = y < ax ? ax : y;
  const float t = hi > 0.0f ? lo / hi : 0.0f;
  float r = prismoid_atan_unit(t);
  r = y > ax ? 1.5707964f - r : r;
  return x < 0.0f ? 3.1415927f - r : r;
}

PRISMOID_SHARED_END

#endif
