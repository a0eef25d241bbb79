#include "app/viewer/tf_edit.hpp"

#include <algorithm>
#include <cmath>

namespace prismoid::app {

size_t add_opacity_point(volume::TransferFunction& tf, double x, double opacity) {
  const volume::OpacityPoint p{std::clamp(x, 0.0, 1.0), std::clamp(opacity, 0.0, 1.0)};
  const auto at = std::upper_bound(tf.opacity.begin(), tf.opacity.end(), p.x,
                                   [](double v, const volume::OpacityPoint& q) { return v < q.x; });
  const auto inserted = tf.opacity.insert(at, p);  // may reallocate: begin() only after it
  return size_t(inserted - tf.opacity.begin());
}

bool remove_opacity_point(volume::TransferFunction& tf, size_t i) {
  if (tf.opacity.size() <= 1 || i >= tf.opacity.size()) return false;
  tf.opacity.erase(tf.opacity.begin() + std::ptrdiff_t(i));
  return true;
}

void move_opacity_point(volume::TransferFunction& tf, size_t i, double x, double opacity) {
  if (i >= tf.opacity.size()) return;
  const double lo = i > 0 ? tf.opacity[i - 1].x : 0.0;
  const double hi = i + 1 < tf.opacity.size() ? tf.opacity[i + 1].x : 1.0;
  tf.opacity[i] = {std::clamp(x, lo, hi), std::clamp(opacity, 0.0, 1.0)};
}

size_t nearest_opacity_point(const volume::TransferFunction& tf, double x, double opacity, double radius) {
  size_t best = tf.opacity.size();
  double best_distance = radius;
  for (size_t i = 0; i < tf.opacity.size(); ++i) {
    const double d = std::hypot(tf.opacity[i].x - x, tf.opacity[i].opacity - opacity);
    if (d <= best_distance) {
      best = i;
      best_distance = d;
    }
  }
  return best;
}

}  // namespace prismoid::app
