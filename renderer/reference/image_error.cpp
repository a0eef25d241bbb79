#include "renderer/reference/image_error.hpp"

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
