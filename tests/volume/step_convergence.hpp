#pragma once
// Second-order convergence of a marched image in its step: with images at steps S, S/2, S/4...
// the largest change between consecutive images should shrink about 4x per halving (the
// midpoint rule's error is O(S^2)); snapping cancels between images of the same proxies.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace prismoid::test {

inline void expect_second_order_in_step(const std::vector<double>& steps, const std::vector<std::vector<float>>& images) {
  std::vector<double> change;
  for (size_t k = 0; k + 1 < images.size(); ++k) {
    double d = 0.0;
    for (size_t i = 0; i < images[k].size(); ++i) d = std::max(d, std::abs(double(images[k][i]) - double(images[k + 1][i])));
    change.push_back(d);
  }
  for (size_t k = 0; k + 1 < change.size(); ++k) {
    const double ratio = change[k] / change[k + 1];
    std::printf("step %.4f -> %.4f: max change %.3g; next halving %.3g; ratio %.2f\n", steps[k], steps[k + 1], change[k],
                change[k + 1], ratio);
    EXPECT_GE(ratio, 2.5);
    EXPECT_LE(ratio, 6.0);
  }
}

}  // namespace prismoid::test
