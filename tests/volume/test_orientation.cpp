#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "renderer/volume/orientation.hpp"

namespace prismoid::volume {
namespace {

// Integer coordinates below 2^38 make the determinant of the differences exact in 128-bit
// integers (each triple product < 2^120), which is the ground truth the predicate must match.
using Int3 = std::array<int64_t, 3>;
__extension__ typedef __int128 Int128;  // GCC/Clang's 128-bit integer (not ISO C++)

int exact_sign(const Int3& a, const Int3& b, const Int3& c, const Int3& d) {
  Int128 u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k], w[k] = d[k] - a[k];
  const Int128 det = u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

// Scaled by 2^-30 so the coordinates are not integers (still exact dyadic doubles); a positive
// scale does not change the sign.
glm::dvec3 to_double(const Int3& p) { return glm::dvec3(double(p[0]), double(p[1]), double(p[2])) * std::ldexp(1.0, -30); }

int naive_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const glm::dvec3 u = b - a, v = c - a, w = d - a;
  const double det = u.x * (v.y * w.z - v.z * w.y) + u.y * (v.z * w.x - v.x * w.z) + u.z * (v.x * w.y - v.y * w.x);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

TEST(Orient3d, MatchesExactIntegerDeterminantOnNearlyCoplanarPoints) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int64_t> coord(-(int64_t(1) << 37), int64_t(1) << 37);
  std::uniform_int_distribution<int64_t> weight(0, 1 << 20), nudge(-1, 1);
  int naive_wrong = 0, zeros = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Int3 a = {coord(rng), coord(rng), coord(rng)};
    Int3 b = {coord(rng), coord(rng), coord(rng)}, c = {coord(rng), coord(rng), coord(rng)};
    Int3 d;
    if (trial % 2 == 0) {
      // d = a + s (b - a) + t (c - a) for s, t in [0, 1], rounded to integers, then nudged by
      // at most one unit: coplanar, or as nearly as integers allow.
      const int64_t s = weight(rng), t = weight(rng);
      for (int k = 0; k < 3; ++k)
        d[k] = a[k] + int64_t((Int128(b[k] - a[k]) * s + Int128(c[k] - a[k]) * t) >> 21) + nudge(rng);
    } else {
      // Four points within a unit or two of one line: b - a = 2^20 w, c - a = s w + e and
      // d - a = t w + f with e, f in {-1, 0, 1}^3, so det = 2^20 det[w, e, f]: at most ~2^40
      // while the products are ~2^114 (double rounding ~2^61), and zero whenever e, f and w
      // are coplanar (e = 0, f = 0, e = +-f, ...).
      const Int3 w = {coord(rng) >> 20, coord(rng) >> 20, coord(rng) >> 20};
      const int64_t s = weight(rng), t = weight(rng);
      for (int k = 0; k < 3; ++k) {
        b[k] = a[k] + (w[k] << 20);
        c[k] = a[k] + s * w[k] + nudge(rng);
        d[k] = a[k] + t * w[k] + nudge(rng);
      }
    }
    const int truth = exact_sign(a, b, c, d);
    const glm::dvec3 pa = to_double(a), pb = to_double(b), pc = to_double(c), pd = to_double(d);
    ASSERT_EQ(orient3d_sign(pa, pb, pc, pd), truth) << "trial " << trial;
    // Permuting the points multiplies the sign by the permutation's sign.
    ASSERT_EQ(orient3d_sign(pb, pa, pc, pd), -truth);
    ASSERT_EQ(orient3d_sign(pd, pa, pb, pc), -truth);  // a 4-cycle is odd
    ASSERT_EQ(orient3d_sign(pc, pd, pa, pb), truth);   // two swaps
    naive_wrong += naive_sign(pa, pb, pc, pd) != truth;
    zeros += truth == 0;
  }
  // The cases must be hard enough that plain double arithmetic gets some wrong (so the exact
  // path ran), and include exactly coplanar ones.
  std::printf("[ cases ] plain double wrong %d of 20000, exactly coplanar %d\n", naive_wrong, zeros);
  EXPECT_GT(naive_wrong, 1000);
  EXPECT_GT(zeros, 100);
}

TEST(Orient3d, SignConvention) {
  const glm::dvec3 o(0.0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  EXPECT_EQ(orient3d_sign(o, x, y, z), 1);   // det[x, y, z] = 1
  EXPECT_EQ(orient3d_sign(o, y, x, z), -1);
  EXPECT_EQ(orient3d_sign(o, x, y, glm::dvec3(0.3, 0.7, 0.0)), 0);
  // Far from the origin, where differences round: points on a plane x + y + z = 3e8 with
  // coordinates exactly representable.
  const glm::dvec3 a(1e8, 1e8, 1e8), b(1e8 + 0.5, 1e8 - 0.25, 1e8 - 0.25), c(1e8 - 0.125, 1e8 + 0.0625, 1e8 + 0.0625);
  EXPECT_EQ(orient3d_sign(a, b, c, glm::dvec3(1e8 + 3.0, 1e8 - 1.0, 1e8 - 2.0)), 0);
}

}  // namespace
}  // namespace prismoid::volume
