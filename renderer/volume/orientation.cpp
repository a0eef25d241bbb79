#include "renderer/volume/orientation.hpp"

#include <array>
#include <cassert>
#include <cmath>
#include <limits>

namespace prismoid::volume {
namespace {

// A sum of doubles kept exactly as a non-overlapping expansion: components ordered by
// increasing magnitude, no two overlapping in their significant bits, zeros dropped. Its sign
// is the sign of its largest component. (Knuth's two-sum and Shewchuk's grow-expansion.)
class ExactSum {
 public:
  void add(double b) {
    double q = b;
    int kept = 0;
    for (int i = 0; i < size_; ++i) {
      const double sum = q + parts_[i];
      const double b_virtual = sum - q;
      const double a_virtual = sum - b_virtual;
      const double error = (q - a_virtual) + (parts_[i] - b_virtual);
      q = sum;
      if (error != 0.0) parts_[kept++] = error;
    }
    if (q != 0.0) parts_[kept++] = q;
    size_ = kept;
    assert(size_ < int(parts_.size()));
  }
  // x * y * z, exactly: x * y = p + e (e recovered by a fused multiply-add, which rounds once
  // a value that is representable), then p * z and e * z split the same way.
  void add_product(double x, double y, double z, double sign) {
    const double p = x * y;
    const double e = std::fma(x, y, -p);
    const double pz = p * z, ez = e * z;
    add(sign * pz);
    add(sign * std::fma(p, z, -pz));
    add(sign * ez);
    add(sign * std::fma(e, z, -ez));
  }
  int sign() const { return size_ == 0 ? 0 : (parts_[size_ - 1] > 0.0 ? 1 : -1); }

 private:
  // 24 triple products of 4 parts each; every add grows the expansion by at most one part.
  std::array<double, 100> parts_{};
  int size_ = 0;
};

// det3(u, v, w) = u . (v x w) as its six signed triple products.
void add_det3(ExactSum& sum, const glm::dvec3& u, const glm::dvec3& v, const glm::dvec3& w, double sign) {
  sum.add_product(u.x, v.y, w.z, sign);
  sum.add_product(u.x, v.z, w.y, -sign);
  sum.add_product(u.y, v.z, w.x, sign);
  sum.add_product(u.y, v.x, w.z, -sign);
  sum.add_product(u.z, v.x, w.y, sign);
  sum.add_product(u.z, v.y, w.x, -sign);
}

int orient3d_exact(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  // The differences b - a etc. are not exact in floating point, so expand instead the 4x4
  // determinant with rows (p, 1), which equals -det[b - a, c - a, d - a], along its last column:
  // det[b - a, c - a, d - a] = det3(b,c,d) - det3(a,c,d) + det3(a,b,d) - det3(a,b,c).
  ExactSum sum;
  add_det3(sum, b, c, d, 1.0);
  add_det3(sum, a, c, d, -1.0);
  add_det3(sum, a, b, d, 1.0);
  add_det3(sum, a, b, c, -1.0);
  return sum.sign();
}

}  // namespace

int orient3d_sign(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  const glm::dvec3 u = b - a, v = c - a, w = d - a;
  const double vw_x = v.y * w.z - v.z * w.y, vw_y = v.z * w.x - v.x * w.z, vw_z = v.x * w.y - v.y * w.x;
  const double det = u.x * vw_x + u.y * vw_y + u.z * vw_z;
  const double permanent = std::abs(u.x) * (std::abs(v.y * w.z) + std::abs(v.z * w.y)) +
                           std::abs(u.y) * (std::abs(v.z * w.x) + std::abs(v.x * w.z)) +
                           std::abs(u.z) * (std::abs(v.x * w.y) + std::abs(v.y * w.x));
  // Each of the six terms meets at most 8 roundings on its way into det (3 differences, 2
  // products, the inner subtraction, 2 outer additions), so |det - exact| <= ((1+eps)^8 - 1)
  // times the exact permanent, about 8 eps times the computed one. 16 eps leaves room for the
  // rounding of the permanent and of this bound itself.
  constexpr double kEps = std::numeric_limits<double>::epsilon() * 0.5;  // unit roundoff
  const double bound = 16.0 * kEps * permanent;
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return orient3d_exact(a, b, c, d);
}

}  // namespace prismoid::volume
