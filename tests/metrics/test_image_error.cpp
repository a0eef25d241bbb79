#include "renderer/metrics/image_error.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>

namespace prismoid::reference {
namespace {

TEST(ImageError, KnownDifferences) {
  // Differences 0, 0.1, -0.2, 0.2: rmse = sqrt((0 + 0.01 + 0.04 + 0.04) / 4) = 0.15.
  const std::vector<float> ref{0.5f, 0.5f, 0.5f, 0.5f};
  const std::vector<float> test{0.5f, 0.6f, 0.3f, 0.7f};
  const ImageError e = image_error(test, ref, 1.0);
  EXPECT_EQ(e.values, 4u);
  EXPECT_EQ(e.non_finite, 0u);
  EXPECT_NEAR(e.rmse, 0.15, 1e-7);
  EXPECT_NEAR(e.max_abs, 0.2, 1e-7);
  EXPECT_NEAR(e.mean_abs, 0.125, 1e-7);
  EXPECT_NEAR(e.psnr_db, 20.0 * std::log10(1.0 / 0.15), 1e-5);
  EXPECT_TRUE(e.max_index == 2 || e.max_index == 3);  // two differences of 0.2 (in float: either)
}

TEST(ImageError, IdenticalImagesHaveInfinitePsnr) {
  const std::vector<float> a{0.1f, 0.2f, 0.3f};
  const ImageError e = image_error(a, a, 1.0);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_EQ(e.max_abs, 0.0);
  EXPECT_TRUE(std::isinf(e.psnr_db));
}

TEST(ImageError, SkipsUncomparedChannelsAndCountsNonFinite) {
  // RGBA, compare RGB: the alpha differences (9) must not count; one NaN is counted, not averaged.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> ref{0, 0, 0, 0, 1, 1, 1, 0};
  const std::vector<float> test{0, 0, 0.5f, 9, nan, 1, 1, 9};
  const ImageError e = image_error(test, ref, 1.0, 4, 3);
  EXPECT_EQ(e.values, 5u);
  EXPECT_EQ(e.non_finite, 1u);
  EXPECT_NEAR(e.max_abs, 0.5, 1e-7);
  EXPECT_EQ(e.max_index, 2u);
  EXPECT_NEAR(e.rmse, std::sqrt(0.25 / 5.0), 1e-7);
}

TEST(ImageError, RejectsMismatchedLayouts) {
  const std::vector<float> a(8), b(4), c(6);
  EXPECT_THROW(image_error(a, b, 1.0), std::invalid_argument);
  EXPECT_THROW(image_error(c, c, 1.0, 4, 3), std::invalid_argument);  // 6 values are not whole RGBA pixels
  EXPECT_THROW(image_error(a, a, 1.0, 4, 5), std::invalid_argument);
}

TEST(ErrorHeatMap, BrightnessGrowsWithErrorAndNonFiniteIsMagenta) {
  // Four one-channel pixels with errors 0, 0.25, 0.5, 1 (scale 1) and one NaN pixel.
  const std::vector<float> ref{0, 0, 0, 0, 0};
  const std::vector<float> test{0, 0.25f, -0.5f, 1, std::numeric_limits<float>::quiet_NaN()};
  const std::vector<float> map = error_heat_map(test, ref, 1, 1, 1.0);
  ASSERT_EQ(map.size(), 20u);
  auto luminance = [&](size_t p) {
    return 0.2126 * double(map[4 * p]) + 0.7152 * double(map[4 * p + 1]) + 0.0722 * double(map[4 * p + 2]);
  };
  EXPECT_EQ(luminance(0), 0.0);
  EXPECT_LT(luminance(0), luminance(1));
  EXPECT_LT(luminance(1), luminance(2));
  EXPECT_LT(luminance(2), luminance(3));
  EXPECT_NEAR(luminance(3), 1.0, 1e-6);  // the scale maps to white
  EXPECT_EQ(map[16], 1.0f);
  EXPECT_EQ(map[17], 0.0f);
  EXPECT_EQ(map[18], 1.0f);
  // scale <= 0: the image's own maximum error (1) is white.
  EXPECT_EQ(error_heat_map(test, ref, 1, 1, 0.0), map);
}

// Two constant images a and b: every window has zero variance and covariance, so the contrast and
// structure term is C2 / C2 = 1 and SSIM is the luminance term (2ab + C1) / (a^2 + b^2 + C1).
TEST(Ssim, ConstantImagesGiveTheLuminanceTermInClosedForm) {
  const uint32_t w = 20, h = 16;
  const std::vector<float> a(w * h, 0.25f), b(w * h, 0.75f);
  const double c1 = 0.01 * 0.01;
  EXPECT_NEAR(ssim(a, b, w, h, 1.0), (2.0 * 0.25 * 0.75 + c1) / (0.25 * 0.25 + 0.75 * 0.75 + c1), 1e-12);
  EXPECT_NEAR(ssim(a, a, w, h, 1.0), 1.0, 1e-12);
}

// Identical textured images give 1; noise lowers it, more noise lowers it more, and the measure
// is symmetric in its arguments.
TEST(Ssim, NoiseLowersItMonotonicallyAndSymmetrically) {
  const uint32_t w = 32, h = 24;
  std::vector<float> img(w * h), little(w * h), more(w * h);
  uint32_t state = 12345u;
  auto noise = [&] {
    state = state * 1664525u + 1013904223u;
    return double(state >> 8) / double(1u << 24) - 0.5;
  };
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      img[i] = float(0.5 + 0.3 * std::sin(0.4 * x) * std::cos(0.3 * y));
      const double n = noise();
      little[i] = float(double(img[i]) + 0.02 * n);
      more[i] = float(double(img[i]) + 0.2 * n);
    }
  EXPECT_NEAR(ssim(img, img, w, h, 1.0), 1.0, 1e-12);
  const double s_little = ssim(little, img, w, h, 1.0), s_more = ssim(more, img, w, h, 1.0);
  EXPECT_LT(s_little, 1.0);
  EXPECT_LT(s_more, s_little);
  EXPECT_NEAR(ssim(img, more, w, h, 1.0), s_more, 1e-12);
}

TEST(Ssim, ComparesOnlyTheChosenChannelsAndRejectsNonFinite) {
  const uint32_t w = 12, h = 12;
  std::vector<float> a(w * h * 4, 0.5f), b = a;
  for (size_t p = 0; p < size_t(w) * h; ++p) b[4 * p + 3] = 0.0f;  // alpha differs everywhere
  EXPECT_NEAR(ssim(a, b, w, h, 1.0, 4, 3), 1.0, 1e-12);
  EXPECT_LT(ssim(a, b, w, h, 1.0, 4, 4), 1.0);
  b[0] = std::numeric_limits<float>::infinity();
  EXPECT_TRUE(std::isnan(ssim(a, b, w, h, 1.0, 4, 3)));
  EXPECT_THROW(ssim(a, b, w + 1, h, 1.0, 4, 3), std::invalid_argument);
}

}  // namespace
}  // namespace prismoid::reference
