#include "renderer/metrics/image_error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace prismoid::reference {

namespace {

void check_layout(size_t test, size_t reference, size_t channels, size_t compared) {
  if (test != reference) throw std::invalid_argument("image_error: the images differ in size");
  if (channels == 0 || compared == 0 || compared > channels || test % channels != 0)
    throw std::invalid_argument("image_error: channels must divide the image and compared must be in [1, channels]");
}

// Black -> red -> yellow -> white in equal thirds: luminance rises monotonically, so larger
// errors always look brighter, in colour or in grey.
void ramp(double t, float* rgba) {
  t = std::clamp(t, 0.0, 1.0);
  rgba[0] = float(std::min(1.0, 3.0 * t));
  rgba[1] = float(std::clamp(3.0 * t - 1.0, 0.0, 1.0));
  rgba[2] = float(std::clamp(3.0 * t - 2.0, 0.0, 1.0));
  rgba[3] = 1.0f;
}

}  // namespace

ImageError image_error(std::span<const float> test, std::span<const float> reference, double peak, size_t channels,
                       size_t compared) {
  check_layout(test.size(), reference.size(), channels, compared);
  ImageError e;
  double sum_sq = 0.0, sum_abs = 0.0;
  for (size_t i = 0; i < test.size(); ++i) {
    if (i % channels >= compared) continue;
    const double a = test[i], b = reference[i];
    if (!std::isfinite(a) || !std::isfinite(b)) {
      ++e.non_finite;
      continue;
    }
    const double d = std::abs(a - b);
    sum_sq += d * d;
    sum_abs += d;
    if (d > e.max_abs || e.values == 0) {
      e.max_abs = d;
      e.max_index = i;
    }
    ++e.values;
  }
  if (e.values > 0) {
    e.rmse = std::sqrt(sum_sq / double(e.values));
    e.mean_abs = sum_abs / double(e.values);
  }
  e.psnr_db = e.rmse > 0.0 ? 20.0 * std::log10(peak / e.rmse) : std::numeric_limits<double>::infinity();
  return e;
}

namespace {

// Filters `v` (width x height) with the normalized 1-D kernel along x then y, keeping only the
// pixels whose whole window lies inside: (width - k + 1) x (height - k + 1) values.
std::vector<double> filter_valid(const std::vector<double>& v, uint32_t width, uint32_t height, const std::vector<double>& kernel) {
  const uint32_t k = uint32_t(kernel.size()), w = width - k + 1, h = height - k + 1;
  std::vector<double> rows(size_t(w) * height), out(size_t(w) * h);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      double sum = 0.0;
      for (uint32_t i = 0; i < k; ++i) sum += kernel[i] * v[size_t(y) * width + x + i];
      rows[size_t(y) * w + x] = sum;
    }
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      double sum = 0.0;
      for (uint32_t i = 0; i < k; ++i) sum += kernel[i] * rows[size_t(y + i) * w + x];
      out[size_t(y) * w + x] = sum;
    }
  return out;
}

}  // namespace

double ssim(std::span<const float> test, std::span<const float> reference, uint32_t width, uint32_t height, double peak,
            size_t channels, size_t compared) {
  check_layout(test.size(), reference.size(), channels, compared);
  if (size_t(width) * height * channels != test.size()) throw std::invalid_argument("ssim: width x height x channels is not the image's size");
  if (width == 0 || height == 0 || !(peak > 0.0)) throw std::invalid_argument("ssim: an empty image or a non-positive peak");
  uint32_t k = std::min<uint32_t>(11, std::min(width, height));
  if (k % 2 == 0) --k;
  std::vector<double> kernel(k);
  double total = 0.0;
  for (uint32_t i = 0; i < k; ++i) {
    const double d = double(i) - double(k / 2);
    total += kernel[i] = std::exp(-d * d / (2.0 * 1.5 * 1.5));
  }
  for (double& g : kernel) g /= total;
  const double c1 = (0.01 * peak) * (0.01 * peak), c2 = (0.03 * peak) * (0.03 * peak);
  const size_t pixels = size_t(width) * height;
  double sum = 0.0;
  size_t count = 0;
  for (size_t c = 0; c < compared; ++c) {
    std::vector<double> x(pixels), y(pixels), xx(pixels), yy(pixels), xy(pixels);
    for (size_t p = 0; p < pixels; ++p) {
      x[p] = test[p * channels + c];
      y[p] = reference[p * channels + c];
      if (!std::isfinite(x[p]) || !std::isfinite(y[p])) return std::numeric_limits<double>::quiet_NaN();
      xx[p] = x[p] * x[p], yy[p] = y[p] * y[p], xy[p] = x[p] * y[p];
    }
    const auto mx = filter_valid(x, width, height, kernel), my = filter_valid(y, width, height, kernel);
    const auto mxx = filter_valid(xx, width, height, kernel), myy = filter_valid(yy, width, height, kernel);
    const auto mxy = filter_valid(xy, width, height, kernel);
    for (size_t i = 0; i < mx.size(); ++i) {
      // Variances can come out a rounding below zero for flat windows: clamp.
      const double vx = std::max(0.0, mxx[i] - mx[i] * mx[i]), vy = std::max(0.0, myy[i] - my[i] * my[i]);
      const double cov = mxy[i] - mx[i] * my[i];
      sum += (2.0 * mx[i] * my[i] + c1) * (2.0 * cov + c2) / ((mx[i] * mx[i] + my[i] * my[i] + c1) * (vx + vy + c2));
      ++count;
    }
  }
  return sum / double(count);
}

std::vector<float> error_heat_map(std::span<const float> test, std::span<const float> reference, size_t channels,
                                  size_t compared, double scale) {
  check_layout(test.size(), reference.size(), channels, compared);
  const size_t pixels = test.size() / channels;
  std::vector<double> worst(pixels, 0.0);
  std::vector<bool> bad(pixels, false);
  for (size_t p = 0; p < pixels; ++p)
    for (size_t c = 0; c < compared; ++c) {
      const double a = test[p * channels + c], b = reference[p * channels + c];
      if (!std::isfinite(a) || !std::isfinite(b)) bad[p] = true;
      else worst[p] = std::max(worst[p], std::abs(a - b));
    }
  if (scale <= 0.0) scale = *std::max_element(worst.begin(), worst.end());
  std::vector<float> rgba(pixels * 4);
  for (size_t p = 0; p < pixels; ++p) {
    if (bad[p]) {
      rgba[4 * p + 0] = 1.0f, rgba[4 * p + 1] = 0.0f, rgba[4 * p + 2] = 1.0f, rgba[4 * p + 3] = 1.0f;
      continue;
    }
    ramp(scale > 0.0 ? worst[p] / scale : 0.0, &rgba[4 * p]);
  }
  return rgba;
}

}  // namespace prismoid::reference
