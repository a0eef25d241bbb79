#include "renderer/metrics/flip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

// LDR-FLIP (Andersson et al. 2020) against hand computations. The expectations are computed
// here from the paper's formulas, independently of renderer/metrics/flip.cpp: colorimetry from
// the sRGB chromaticities, and (last test) the whole pipeline with the paper's 2-D kernels
// convolved directly, against which the separable passes must agree.

namespace prismoid::reference {
namespace {

using Rgb = std::array<double, 3>;
constexpr double kPi = std::numbers::pi;

// --- Hand colorimetry: sRGB primaries and D65 white to the RGB -> XYZ matrix, Cramer's rule.
struct Hand {
  double m[3][3];
  double white[3];
};

double det3(const double a[3][3]) {
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

Hand hand() {
  const double x[3] = {0.64, 0.30, 0.15}, y[3] = {0.33, 0.60, 0.06};
  const double w[3] = {0.3127 / 0.3290, 1.0, (1.0 - 0.3127 - 0.3290) / 0.3290};
  double p[3][3];
  for (int c = 0; c < 3; ++c) p[0][c] = x[c] / y[c], p[1][c] = 1.0, p[2][c] = (1.0 - x[c] - y[c]) / y[c];
  Hand h{};
  const double d = det3(p);
  for (int c = 0; c < 3; ++c) {
    double q[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) q[i][j] = j == c ? w[i] : p[i][j];
    const double s = det3(q) / d;
    for (int r = 0; r < 3; ++r) h.m[r][c] = p[r][c] * s;
  }
  for (int r = 0; r < 3; ++r) h.white[r] = h.m[r][0] + h.m[r][1] + h.m[r][2];
  return h;
}

Rgb to_xyz(const Rgb& c) {
  const Hand h = hand();
  Rgb o{};
  for (int r = 0; r < 3; ++r) o[size_t(r)] = h.m[r][0] * c[0] + h.m[r][1] * c[1] + h.m[r][2] * c[2];
  return o;
}

Rgb from_xyz(const Rgb& xyz) {
  const Hand h = hand();
  double inv[3][3];  // adjugate / determinant
  const double d = det3(h.m);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      inv[i][j] = (h.m[r0][c0] * h.m[r1][c1] - h.m[r0][c1] * h.m[r1][c0]) / d;
    }
  Rgb o{};
  for (int i = 0; i < 3; ++i) o[size_t(i)] = inv[i][0] * xyz[0] + inv[i][1] * xyz[1] + inv[i][2] * xyz[2];
  return o;
}

// Linear RGB <-> the opponent space YCxCz the CSFs filter in.
Rgb to_ycxcz(const Rgb& rgb) {
  const Hand h = hand();
  const Rgb xyz = to_xyz(rgb);
  const double X = xyz[0] / h.white[0], Y = xyz[1] / h.white[1], Z = xyz[2] / h.white[2];
  return {116 * Y - 16, 500 * (X - Y), 200 * (Y - Z)};
}
Rgb ycxcz_to_rgb(const Rgb& o) {
  const Hand h = hand();
  const double Y = (o[0] + 16) / 116;
  return from_xyz({(Y + o[1] / 500) * h.white[0], Y * h.white[1], (Y - o[2] / 200) * h.white[2]});
}

double lab_f(double t) {
  const double d = 6.0 / 29.0;
  return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

Rgb hunt_lab(const Rgb& rgb) {
  const Hand h = hand();
  const Rgb xyz = to_xyz(rgb);
  const double fx = lab_f(xyz[0] / h.white[0]), fy = lab_f(xyz[1] / h.white[1]), fz = lab_f(xyz[2] / h.white[2]);
  const double l = 116.0 * fy - 16.0;
  return {l, 0.01 * l * 500.0 * (fx - fy), 0.01 * l * 200.0 * (fy - fz)};
}

double hyab(const Rgb& a, const Rgb& b) { return std::abs(a[0] - b[0]) + std::hypot(a[1] - b[1], a[2] - b[2]); }
double cmax() { return std::pow(hyab(hunt_lab({0, 1, 0}), hunt_lab({0, 0, 1})), 0.7); }
double remap(double e) {
  const double knee = 0.4 * cmax();
  return e < knee ? 0.95 * e / knee : 0.95 + (e - knee) / (cmax() - knee) * 0.05;
}
// FLIP of two flat fields: the CSFs keep a constant, features are zero, so colour alone.
double flat_flip(const Rgb& a, const Rgb& b) { return remap(std::pow(hyab(hunt_lab(a), hunt_lab(b)), 0.7)); }

std::vector<float> uniform(uint32_t w, uint32_t h, uint32_t stride, const Rgb& c) {
  std::vector<float> img(size_t(w) * h * stride, 1.0f);
  for (size_t p = 0; p < size_t(w) * h; ++p)
    for (size_t k = 0; k < 3; ++k) img[p * stride + k] = float(c[k]);
  return img;
}

std::vector<float> random_image(uint32_t w, uint32_t h, uint32_t stride, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> img(size_t(w) * h * stride);
  for (float& v : img) v = u(rng);
  return img;
}

void put(std::vector<float>& img, uint32_t w, uint32_t stride, uint32_t x, uint32_t y, const Rgb& c) {
  for (size_t k = 0; k < 3; ++k) img[(size_t(y) * w + x) * stride + k] = float(c[k]);
}

TEST(Flip, DerivedMatrixIsTheSrgbStandardsMatrix) {
  // IEC 61966-2-1's RGB -> XYZ matrix, printed to four decimals.
  const double standard[3][3] = {{0.4124, 0.3576, 0.1805}, {0.2126, 0.7152, 0.0722}, {0.0193, 0.1192, 0.9505}};
  const Hand h = hand();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(h.m[r][c], standard[r][c], 5e-5) << r << ',' << c;
  EXPECT_NEAR(h.white[1], 1.0, 1e-15);
}

TEST(Flip, IdenticalImagesAreExactlyZero) {
  const auto a = random_image(37, 23, 4, 1);
  const FlipResult f = flip(a, a, 37, 23, 4);
  ASSERT_EQ(f.map.size(), 37u * 23u);
  for (float v : f.map) ASSERT_EQ(v, 0.0f);
  EXPECT_EQ(f.mean, 0.0);
  EXPECT_EQ(f.max, 0.0);
  EXPECT_EQ(f.non_finite, 0u);
}

TEST(Flip, MapIsInUnitIntervalAndSymmetric) {
  // Both terms are symmetric by construction (HyAB is a distance; the feature term compares
  // |response| of the two images by absolute difference), so swapping test and reference must
  // give the same map bit for bit.
  const auto a = random_image(41, 29, 3, 2), b = random_image(41, 29, 3, 3);
  const FlipResult ab = flip(a, b, 41, 29, 3), ba = flip(b, a, 41, 29, 3);
  ASSERT_EQ(ab.map.size(), ba.map.size());
  for (size_t i = 0; i < ab.map.size(); ++i) {
    ASSERT_GE(ab.map[i], 0.0f);
    ASSERT_LE(ab.map[i], 1.0f);
    ASSERT_EQ(ab.map[i], ba.map[i]) << i;
  }
  EXPECT_EQ(ab.mean, ba.mean);
  EXPECT_EQ(ab.max, ba.max);
  EXPECT_GT(ab.mean, 0.1);  // independent noise images differ visibly
}

TEST(Flip, FlatGreyChangeMatchesHandComputation) {
  // Greys have a* = b* = 0 and Y/Yn = v, so HyAB = |L1 - L2| = 116 (cbrt 0.5 - cbrt 0.25)
  // = 18.9938; 18.9938^0.7 = 7.852, below the knee 0.4 cmax = 16.51, so FLIP = 0.95 * 7.852 /
  // 16.51 = 0.4518 at every pixel (borders included: the CSFs clamp to the edge).
  const double dl = 116.0 * (std::cbrt(0.5) - std::cbrt(0.25));
  const double expected = 0.95 * std::pow(dl, 0.7) / (0.4 * cmax());
  EXPECT_NEAR(expected, 0.4518, 1e-4);
  EXPECT_NEAR(expected, flat_flip({0.5, 0.5, 0.5}, {0.25, 0.25, 0.25}), 1e-12);
  const FlipResult f = flip(uniform(16, 12, 4, {0.5, 0.5, 0.5}), uniform(16, 12, 4, {0.25, 0.25, 0.25}), 16, 12, 4);
  for (float v : f.map) ASSERT_NEAR(v, expected, 1e-7);
  EXPECT_NEAR(f.mean, expected, 1e-12);
  EXPECT_NEAR(f.max, expected, 1e-12);
}

TEST(Flip, FlatColourChangeMatchesHandComputation) {
  // A chromatic change: the Hunt-adjusted a*, b* count as well as L* (0.4645 here).
  const Rgb a{0.75, 0.25, 0.125}, b{0.625, 0.375, 0.125};  // exact in float
  const double expected = flat_flip(a, b);
  const FlipResult f = flip(uniform(9, 7, 3, a), uniform(9, 7, 3, b), 9, 7, 3);
  for (float v : f.map) ASSERT_NEAR(v, expected, 1e-7);
  EXPECT_NEAR(f.mean, expected, 1e-12);
  EXPECT_GT(expected, 0.2);
  EXPECT_LT(expected, 0.95);
}

TEST(Flip, GreenAgainstBlueIsTheMaximumAndMapsToOne) {
  // The paper normalizes by cmax, the Hunt-adjusted HyAB^0.7 of pure green against pure blue:
  // HyAB 203.30, cmax 41.28, so that pair maps to exactly 1.
  EXPECT_NEAR(hyab(hunt_lab({0, 1, 0}), hunt_lab({0, 0, 1})), 203.30, 0.01);
  const FlipResult gb = flip(uniform(5, 5, 3, {0, 1, 0}), uniform(5, 5, 3, {0, 0, 1}), 5, 5, 3);
  EXPECT_NEAR(gb.mean, 1.0, 1e-12);
  EXPECT_NEAR(gb.max, 1.0, 1e-12);
  // Black against white: HyAB = 100, 100^0.7 = 25.12, above the knee: 0.95 + (25.12 - 16.51) /
  // (41.28 - 16.51) * 0.05 = 0.9674, large but below green/blue.
  const double bw = 0.95 + (std::pow(100.0, 0.7) - 0.4 * cmax()) / (0.6 * cmax()) * 0.05;
  EXPECT_NEAR(bw, 0.9674, 1e-4);
  const FlipResult f = flip(uniform(5, 5, 3, {0, 0, 0}), uniform(5, 5, 3, {1, 1, 1}), 5, 5, 3);
  EXPECT_NEAR(f.mean, bw, 1e-12);
  // No pair of flat colours on a 5^3 grid of the RGB cube exceeds green/blue: the map stays in [0, 1].
  std::vector<Rgb> grid;
  for (int r = 0; r < 5; ++r)
    for (int g = 0; g < 5; ++g)
      for (int b = 0; b < 5; ++b) grid.push_back({r / 4.0, g / 4.0, b / 4.0});
  double largest = 0.0;
  for (size_t i = 0; i < grid.size(); ++i)
    for (size_t j = i + 1; j < grid.size(); ++j) {
      const FlipResult p = flip(uniform(1, 1, 3, grid[i]), uniform(1, 1, 3, grid[j]), 1, 1, 3);
      ASSERT_NEAR(p.max, flat_flip(grid[i], grid[j]), 1e-12);
      largest = std::max(largest, p.max);
    }
  EXPECT_NEAR(largest, 1.0, 1e-12);
}

// A grey background with a centred s x s square of the same luminance but another chroma:
// the feature pipeline sees only luminance, so only the colour pipeline and its CSFs act.
Rgb isoluminant_patch() {
  const Hand h = hand();
  const double dr = 0.3, dg = -h.m[1][0] * dr / h.m[1][1];  // keeps Y = m[1] . rgb unchanged
  return {double(float(0.5 + dr)), double(float(0.5 + dg)), 0.5};  // as the float image holds it
}

double centre_flip(uint32_t s, double ppd) {
  const uint32_t n = 81, c = n / 2;
  const auto ref = uniform(n, n, 4, {0.5, 0.5, 0.5});
  auto test = ref;
  for (uint32_t y = c - s / 2; y <= c + s / 2; ++y)
    for (uint32_t x = c - s / 2; x <= c + s / 2; ++x) put(test, n, 4, x, y, isoluminant_patch());
  return flip(test, ref, n, n, 4, ppd).map[size_t(c) * n + c];
}

// The centre weight of a CSF's normalized 2-D kernel: the paper's spatial kernel
// sum_k a_k sqrt(pi/b_k) exp(-pi^2 x^2 / b_k) at x = 0, over its sum on the (2r+1)^2 grid.
double csf_centre_weight(double a1, double b1, double a2, double b2, double ppd) {
  const int r = int(std::ceil(3.0 * std::sqrt(0.04 / (2 * kPi * kPi)) * ppd));
  auto line_sum = [&](double b) {
    double s = 0.0;
    for (int i = -r; i <= r; ++i) s += std::exp(-kPi * kPi * (i / ppd) * (i / ppd) / b);
    return s;
  };
  const double c1 = a1 * std::sqrt(kPi / b1), c2 = a2 > 0 ? a2 * std::sqrt(kPi / b2) : 0.0;
  const double s1 = line_sum(b1), s2 = a2 > 0 ? line_sum(b2) : 0.0;
  return (c1 + c2) / (c1 * s1 * s1 + c2 * s2 * s2);
}

// Slack for an "isoluminant" patch: the inputs are floats, so the patch keeps the background's
// luminance only to float rounding, |dY| < 1e-7. The feature term sees that as an edge or
// point difference D <= |dY| (each response's positive weights sum to 1), f = (D / sqrt 2)^0.5
// < 3e-4, which lifts a colour term c to c^(1 - f) = c (1 + f ln(1/c) + ...): by less than
// 3e-4 c for c > 0.1.
double isoluminance_slack(double c) { return 3e-4 * c * std::max(1.0, std::log(1.0 / c)); }

TEST(Flip, ContrastSensitivityAttenuatesSmallDifferences) {
  // The chromatic CSFs are low-pass (blue-yellow's widest Gaussian has a standard deviation of
  // sqrt(0.04 / (2 pi^2)) = 0.045 degrees, 3 pixels at 67 ppd): the same colour difference
  // counts less the smaller its patch, rising with the patch to the flat-field value, which a
  // patch wider than the kernels (radius 10 pixels) gives at its centre exactly. Measured at
  // 67 ppd: s = 1: 0.1107, 3: 0.3510, 5: 0.4298, 9: 0.44044, 17: 0.44045, 33 and 65: 0.440449.
  const Rgb grey{0.5, 0.5, 0.5}, patch = isoluminant_patch();
  const double flat = flat_flip(patch, grey);
  double previous = 0.0;
  for (uint32_t s : {1u, 3u, 5u, 9u, 17u, 33u, 65u}) {
    const double v = centre_flip(s, 67.0);
    EXPECT_GT(v, previous - isoluminance_slack(flat)) << "patch " << s;
    EXPECT_LE(v, flat + isoluminance_slack(flat)) << "patch " << s;
    previous = v;
  }
  // No edge within the feature radius (9) and the CSF radius (10) of the centre: exactly flat.
  EXPECT_NEAR(centre_flip(65, 67.0), flat, 1e-7);
  EXPECT_NEAR(centre_flip(33, 67.0), flat, 1e-7);

  // The single pixel by hand: at its centre each opponent channel keeps the centre weight of
  // its kernel times its difference (luminance: none), the rest is the grey background.
  const Rgb bg = to_ycxcz(grey), px = to_ycxcz(patch);
  const double w_a = csf_centre_weight(1, 0.0047, 0, 1, 67.0), w_rg = csf_centre_weight(1, 0.0053, 0, 1, 67.0),
               w_by = csf_centre_weight(34.1, 0.04, 13.5, 0.025, 67.0);
  EXPECT_NEAR(px[0], bg[0], 116 * 1e-7);  // isoluminant to float rounding
  Rgb seen = ycxcz_to_rgb({bg[0] + w_a * (px[0] - bg[0]), bg[1] + w_rg * (px[1] - bg[1]), bg[2] + w_by * (px[2] - bg[2])});
  for (double& v : seen) v = std::clamp(v, 0.0, 1.0);
  const double single = remap(std::pow(hyab(hunt_lab(seen), hunt_lab(grey)), 0.7));
  EXPECT_NEAR(centre_flip(1, 67.0), single, isoluminance_slack(single));
  EXPECT_NEAR(single, 0.1107, 1e-4);
  EXPECT_LT(single, 0.26 * flat);  // a quarter of the flat difference survives
}

TEST(Flip, MorePixelsPerDegreeHideSmallDifferencesButNotFlatOnes) {
  // The paper's observer model: pixels per degree grow with viewing distance, so a one-pixel
  // difference subtends less of the visual field and the CSFs attenuate it more. Measured for
  // the isoluminant pixel: 0.2851 at 33.5 ppd, 0.1107 at 67, 0.0421 at 134.
  const double near = centre_flip(1, 33.5), standard = centre_flip(1, 67.0), far = centre_flip(1, 134.0);
  EXPECT_GT(near, standard);
  EXPECT_GT(standard, far);
  // A flat field has no spatial frequency: its difference is the same at every distance.
  const auto a = uniform(8, 8, 3, {0.7, 0.4, 0.2}), b = uniform(8, 8, 3, {0.3, 0.4, 0.6});
  EXPECT_EQ(flip(a, b, 8, 8, 3, 20.0).mean, flip(a, b, 8, 8, 3, 200.0).mean);
}

TEST(Flip, NonFinitePixelsAreCountedNotAveraged) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const uint32_t w = 20, h = 16;
  // Identical images but for non-finite values: the bad pixels take the other image's colour,
  // so nothing else differs.
  auto a = random_image(w, h, 4, 5);
  auto b = a;
  a[(3 * w + 4) * 4 + 1] = nan;
  b[(10 * w + 11) * 4 + 2] = inf;
  a[(12 * w + 2) * 4 + 0] = nan;
  b[(12 * w + 2) * 4 + 0] = -inf;  // both bad: counted once
  b[(0 * w + 0) * 4 + 3] = nan;    // alpha is not compared
  const FlipResult f = flip(a, b, w, h, 4);
  EXPECT_EQ(f.non_finite, 3u);
  EXPECT_TRUE(std::isnan(f.map[3 * w + 4]));
  EXPECT_TRUE(std::isnan(f.map[10 * w + 11]));
  EXPECT_TRUE(std::isnan(f.map[12 * w + 2]));
  EXPECT_EQ(f.mean, 0.0);
  EXPECT_EQ(f.max, 0.0);
  for (size_t p = 0; p < f.map.size(); ++p)
    if (p != 3 * w + 4 && p != 10 * w + 11 && p != 12 * w + 2) {
      ASSERT_EQ(f.map[p], 0.0f) << p;
    }

  // Different images: the mean is over the finite pixels only.
  auto c = random_image(w, h, 3, 6), d = random_image(w, h, 3, 7);
  c[(7 * w + 7) * 3] = nan;
  const FlipResult g = flip(c, d, w, h, 3);
  EXPECT_EQ(g.non_finite, 1u);
  double sum = 0.0;
  size_t count = 0;
  for (float v : g.map)
    if (std::isfinite(v)) sum += double(v), ++count;
  EXPECT_EQ(count, size_t(w) * h - 1);
  EXPECT_NEAR(g.mean, sum / double(count), 1e-7);
  EXPECT_TRUE(std::isfinite(g.mean));
}

TEST(Flip, RejectsBadArguments) {
  const std::vector<float> a(4 * 4 * 3, 0.5f), b(4 * 4 * 4, 0.5f);
  EXPECT_THROW(flip(a, a, 4, 4, 2), std::invalid_argument);
  EXPECT_THROW(flip(a, b, 4, 4, 3), std::invalid_argument);
  EXPECT_THROW(flip(a, a, 4, 3, 3), std::invalid_argument);
  EXPECT_THROW(flip({}, {}, 0, 0, 3), std::invalid_argument);
  EXPECT_THROW(flip(a, a, 4, 4, 3, 0.0), std::invalid_argument);
  EXPECT_THROW(flip(a, a, 4, 4, 3, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

// --- The paper's pipeline transcribed directly: full 2-D kernels, clamp-to-edge convolution.
struct Direct {
  uint32_t w, h;
  double ppd;

  std::vector<double> convolve(const std::vector<double>& in, const std::vector<double>& k, int r) const {
    std::vector<double> out(in.size());
    const int iw = int(w), ih = int(h), n = 2 * r + 1;
    for (int y = 0; y < ih; ++y)
      for (int x = 0; x < iw; ++x) {
        double s = 0.0;
        for (int j = -r; j <= r; ++j)
          for (int i = -r; i <= r; ++i)
            s += k[size_t((j + r) * n + (i + r))] * in[size_t(std::clamp(y + j, 0, ih - 1) * iw + std::clamp(x + i, 0, iw - 1))];
        out[size_t(y * iw + x)] = s;
      }
    return out;
  }

  std::vector<double> csf_kernel(double a1, double b1, double a2, double b2, int r) const {
    std::vector<double> k;
    double sum = 0.0;
    for (int j = -r; j <= r; ++j)
      for (int i = -r; i <= r; ++i) {
        const double d2 = (i * i + j * j) / (ppd * ppd);
        double v = a1 * std::sqrt(kPi / b1) * std::exp(-kPi * kPi * d2 / b1);
        if (a2 > 0.0) v += a2 * std::sqrt(kPi / b2) * std::exp(-kPi * kPi * d2 / b2);
        k.push_back(v);
        sum += v;
      }
    for (double& v : k) v /= sum;
    return k;
  }

  double feature_sd() const { return 0.5 * 0.082 * ppd; }
  int feature_radius() const { return int(std::ceil(3.0 * feature_sd())); }

  // Edge (order 1) or point (order 2) kernel along x (y if transposed), positive weights
  // normalized to sum 1, negative ones to -1.
  std::vector<double> feature_kernel(int order, bool transpose) const {
    const double sd = feature_sd();
    const int r = feature_radius();
    std::vector<double> k;
    double pos = 0.0, neg = 0.0;
    for (int j = -r; j <= r; ++j)
      for (int i = -r; i <= r; ++i) {
        const double x = transpose ? j : i, g = std::exp(-(i * i + j * j) / (2.0 * sd * sd));
        const double v = order == 1 ? -x * g : (x * x / (sd * sd) - 1.0) * g;
        k.push_back(v);
        (v > 0 ? pos : neg) += std::abs(v);
      }
    for (double& v : k) v = v > 0 ? v / pos : v / neg;
    return k;
  }

  struct Out {
    std::vector<Rgb> lab;
    std::vector<double> edge, point;
  };

  Out run(const std::vector<float>& img, uint32_t stride) const {
    const size_t n = size_t(w) * h;
    std::vector<double> yy(n), cx(n), cz(n), lum(n);
    for (size_t p = 0; p < n; ++p) {
      Rgb c{};
      for (size_t k = 0; k < 3; ++k) c[k] = std::clamp(double(img[p * stride + k]), 0.0, 1.0);
      const Rgb o = to_ycxcz(c);
      yy[p] = o[0], cx[p] = o[1], cz[p] = o[2], lum[p] = (o[0] + 16) / 116;
    }
    const int r = int(std::ceil(3.0 * std::sqrt(0.04 / (2 * kPi * kPi)) * ppd));
    yy = convolve(yy, csf_kernel(1, 0.0047, 0, 1, r), r);
    cx = convolve(cx, csf_kernel(1, 0.0053, 0, 1, r), r);
    cz = convolve(cz, csf_kernel(34.1, 0.04, 13.5, 0.025, r), r);
    Out o;
    for (size_t p = 0; p < n; ++p) {
      Rgb rgb = ycxcz_to_rgb({yy[p], cx[p], cz[p]});
      for (double& v : rgb) v = std::clamp(v, 0.0, 1.0);
      o.lab.push_back(hunt_lab(rgb));
    }
    const int fr = feature_radius();
    const auto ex = convolve(lum, feature_kernel(1, false), fr), ey = convolve(lum, feature_kernel(1, true), fr);
    const auto px = convolve(lum, feature_kernel(2, false), fr), py = convolve(lum, feature_kernel(2, true), fr);
    for (size_t p = 0; p < n; ++p) o.edge.push_back(std::hypot(ex[p], ey[p])), o.point.push_back(std::hypot(px[p], py[p]));
    return o;
  }

  // With `features` false, the colour term alone.
  std::vector<double> flip_map(const std::vector<float>& test, const std::vector<float>& ref, uint32_t stride,
                               bool features = true) const {
    const Out t = run(test, stride), r = run(ref, stride);
    std::vector<double> m;
    for (size_t p = 0; p < t.lab.size(); ++p) {
      const double c = remap(std::pow(hyab(t.lab[p], r.lab[p]), 0.7));
      const double f = std::pow(std::max(std::abs(t.edge[p] - r.edge[p]), std::abs(t.point[p] - r.point[p])) / std::sqrt(2.0), 0.5);
      m.push_back(features ? std::pow(c, 1.0 - f) : c);
    }
    return m;
  }
};

TEST(Flip, SeparablePassesEqualThePapers2DKernels) {
  // Noise with values outside [0, 1] (clamped) on images smaller and larger than the kernels,
  // at the default 67 ppd (CSF radius 10, feature radius 9) and at 20 ppd (radii 3 and 3).
  for (const double ppd : {67.0, 20.0})
    for (const auto& [w, h] : {std::pair<uint32_t, uint32_t>{23, 17}, {7, 30}}) {
      auto a = random_image(w, h, 4, 11), b = random_image(w, h, 4, 12);
      for (size_t i = 0; i < a.size(); i += 7) a[i] = 1.5f * a[i] - 0.2f;
      // A smooth region so small and mid-sized differences are covered too.
      for (size_t p = 0; p < size_t(w) * h / 2; ++p)
        for (size_t k = 0; k < 3; ++k) b[p * 4 + k] = a[p * 4 + k] = 0.3f + 0.01f * float(p % w);
      b[4 * 4 + 1] += 0.02f;
      const FlipResult f = flip(a, b, w, h, 4, ppd);
      const auto direct = Direct{w, h, ppd}.flip_map(a, b, 4);
      double mean = 0.0;
      for (size_t p = 0; p < direct.size(); ++p) {
        // The map is float: rounding to it costs at most 2^-24 of a value in [0, 1].
        ASSERT_NEAR(double(f.map[p]), direct[p], 1e-7) << "ppd " << ppd << " size " << w << 'x' << h << " pixel " << p;
        mean += direct[p];
      }
      EXPECT_NEAR(f.mean, mean / double(direct.size()), 1e-9);
    }
}

TEST(Flip, TheFeatureTermLiftsAnIsolatedBrightPixel) {
  // A firefly, one white pixel on grey 0.2: the CSFs spread it, so its colour term is small,
  // but the point detector finds a point in one image only, and colour^(1 - feature) lifts it
  // (the paper's reason for the feature pipeline). Measured: 0.3924 against a colour term of
  // 0.3167, a feature term f = 1 - ln 0.3924 / ln 0.3167 = 0.19.
  const uint32_t n = 31, c = 15;
  const auto ref = uniform(n, n, 3, {0.2, 0.2, 0.2});
  auto spike = ref;
  put(spike, n, 3, c, c, {1.0, 1.0, 1.0});
  const FlipResult f = flip(spike, ref, n, n, 3);
  const Direct d{n, n, 67.0};
  const double colour_only = d.flip_map(spike, ref, 3, false)[size_t(c) * n + c];
  const double at_spike = f.map[size_t(c) * n + c];
  EXPECT_NEAR(at_spike, d.flip_map(spike, ref, 3)[size_t(c) * n + c], 1e-7);
  EXPECT_GT(at_spike, colour_only + 0.05);
  EXPECT_GT(colour_only, 0.2);
  EXPECT_LT(at_spike, flat_flip({1, 1, 1}, {0.2, 0.2, 0.2}));  // still below the flat change
  EXPECT_EQ(float(f.max), *std::max_element(f.map.begin(), f.map.end()));
  EXPECT_EQ(f.map[0], 0.0f);  // beyond both radii (10 and 9) nothing differs
}

}  // namespace
}  // namespace prismoid::reference
