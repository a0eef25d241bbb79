#include "renderer/metrics/flip.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

// Every constant below is LDR-FLIP's (Andersson et al. 2020, see flip.hpp), cited by the step
// of the paper's colour or feature pipeline it belongs to. The digits were checked against the
// paper's errata (research.nvidia.com/publication/2020-07_FLIP) and the authors' released
// implementation (read to check numbers; no code is taken from it).

namespace prismoid::reference {

namespace {

using Rgb = std::array<double, 3>;
using Matrix = std::array<Rgb, 3>;
using Plane = std::vector<double>;
constexpr double kPi = std::numbers::pi;

Rgb apply(const Matrix& m, const Rgb& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

double determinant(const Matrix& m) {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Matrix inverse(const Matrix& m) {
  const double d = determinant(m);
  Matrix r{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      // Cofactor of m[j][i] (the adjugate is the transposed cofactor matrix).
      const int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
      r[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / d;
    }
  return r;
}

// Linear RGB <-> CIE XYZ for the sRGB primaries (IEC 61966-2-1 / ITU-R BT.709 chromaticities
// R 0.64 0.33, G 0.30 0.60, B 0.15 0.06) and the D65 white (0.3127, 0.3290): the paper works on
// sRGB images and takes XYZ relative to D65 (colour pipeline). The matrix is derived from the
// chromaticities so that RGB white is exactly the reference white; it matches the standard's
// rounded matrix (0.4124 0.3576 0.1805 / 0.2126 0.7152 0.0722 / 0.0193 0.1192 0.9505).
struct Colorimetry {
  Matrix to_xyz{}, from_xyz{};
  Rgb white{};  // XYZ of RGB (1, 1, 1) = D65 with Y = 1
};

Colorimetry make_colorimetry() {
  const double xy[3][2] = {{0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}};
  const double wx = 0.3127, wy = 0.3290;
  Matrix primaries{};
  for (int c = 0; c < 3; ++c) {
    primaries[0][c] = xy[c][0] / xy[c][1];
    primaries[1][c] = 1.0;
    primaries[2][c] = (1.0 - xy[c][0] - xy[c][1]) / xy[c][1];
  }
  const Rgb scale = apply(inverse(primaries), {wx / wy, 1.0, (1.0 - wx - wy) / wy});
  Colorimetry s;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) s.to_xyz[r][c] = primaries[r][c] * scale[c];
  s.from_xyz = inverse(s.to_xyz);
  s.white = apply(s.to_xyz, {1.0, 1.0, 1.0});
  return s;
}

const Colorimetry& colorimetry() {
  static const Colorimetry s = make_colorimetry();
  return s;
}

// Colour pipeline, spatial filtering: the images are filtered in the linear opponent space
// YCxCz (Y 116 Y/Yn - 16, Cx 500 (X/Xn - Y/Yn), Cz 200 (Y/Yn - Z/Zn)), CIELAB's formulas with
// the cube roots left out, so that the achromatic, red-green and blue-yellow channels are
// filtered apart and linearly.
Rgb linear_rgb_to_ycxcz(const Rgb& rgb) {
  const Colorimetry& s = colorimetry();
  const Rgb xyz = apply(s.to_xyz, rgb);
  const double x = xyz[0] / s.white[0], y = xyz[1] / s.white[1], z = xyz[2] / s.white[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Rgb ycxcz_to_linear_rgb(const Rgb& ycxcz) {
  const Colorimetry& s = colorimetry();
  const double y = (ycxcz[0] + 16.0) / 116.0;
  const Rgb xyz{(y + ycxcz[1] / 500.0) * s.white[0], y * s.white[1], (y - ycxcz[2] / 200.0) * s.white[2]};
  return apply(s.from_xyz, xyz);
}

// Colour pipeline, perceptually uniform colour space: CIE L*a*b* (D65, with CIE's linear
// segment below (6/29)^3) of the filtered colour, then the Hunt adjustment a' = 0.01 L* a*,
// b' = 0.01 L* b*, which makes chroma count less in dark colours (the Hunt effect: colourfulness
// grows with luminance).
Rgb hunt_lab(const Rgb& rgb) {
  const Colorimetry& s = colorimetry();
  const Rgb xyz = apply(s.to_xyz, rgb);
  constexpr double delta = 6.0 / 29.0;
  auto f = [&](double t) { return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0; };
  const double fx = f(xyz[0] / s.white[0]), fy = f(xyz[1] / s.white[1]), fz = f(xyz[2] / s.white[2]);
  const double l = 116.0 * fy - 16.0, a = 500.0 * (fx - fy), b = 200.0 * (fy - fz);
  return {l, 0.01 * l * a, 0.01 * l * b};
}

// Colour pipeline, colour metric: HyAB (Abasi et al., cited by the paper), city-block in
// lightness plus Euclidean in the chroma plane, which the paper prefers to Euclidean L*a*b* for
// the large colour differences of rendered images.
double hyab(const Rgb& p, const Rgb& q) {
  const double da = p[1] - q[1], db = p[2] - q[2];  // bounded (|a'|, |b'| < 200): no need for hypot
  return std::abs(p[0] - q[0]) + std::sqrt(da * da + db * db);
}

// Colour metric: the HyAB distance is raised to qc = 0.7; cmax is the largest such value in the
// RGB cube, between pure green and pure blue (Hunt-adjusted): HyAB 203.3, cmax 41.28.
constexpr double kQc = 0.7;
double color_max() {
  static const double cmax = std::pow(hyab(hunt_lab({0.0, 1.0, 0.0}), hunt_lab({0.0, 0.0, 1.0})), kQc);
  return cmax;
}

// Colour metric, remap to [0, 1]: [0, pc cmax) goes linearly to [0, pt) and [pc cmax, cmax] to
// [pt, 1], with pc = 0.4 and pt = 0.95: 95 % of the output for the lower 40 % of the distances.
constexpr double kPc = 0.4, kPt = 0.95;
double remap_color(double e) {
  const double cmax = color_max(), knee = kPc * cmax;
  return e < knee ? kPt * e / knee : kPt + (e - knee) / (cmax - knee) * (1.0 - kPt);
}

// A separable pass's kernel, given by its weights at offsets 1..r (index i - 1), the centre's
// weight implied by the kind:
//   Smooth  symmetric, weights summing to 1:  out = c + sum w_i ((v[+i] - c) + (v[-i] - c))
//   ZeroSum symmetric, weights summing to 0:  out =     sum w_i ((v[+i] - c) + (v[-i] - c))
//   Odd     antisymmetric:                    out =     sum w_i (v[-i] - v[+i])
// These are sum_j w_j v[j] rewritten with the kernel's sum; written this way a constant stays
// exactly constant (smooth) or exactly zero (derivatives), with no rounding of sum w_j.
// Borders clamp to the edge, so a constant image is constant up to its borders.
enum class Kind { Smooth, ZeroSum, Odd };
struct Kernel {
  Kind kind = Kind::Smooth;
  std::vector<double> w;
};

struct Image {
  uint32_t width = 0, height = 0;
  size_t at(uint32_t x, uint32_t y) const { return size_t(y) * width + x; }
};

Plane pass_x(const Plane& in, const Image& im, const Kernel& k) {
  const int r = int(k.w.size()), w = int(im.width);
  Plane out(in.size());
  std::vector<double> row(size_t(w + 2 * r));
  for (uint32_t y = 0; y < im.height; ++y) {
    const double* src = &in[im.at(0, y)];
    for (int x = -r; x < w + r; ++x) row[size_t(x + r)] = src[std::clamp(x, 0, w - 1)];
    const double* v = row.data() + r;
    double* dst = &out[im.at(0, y)];
    for (int x = 0; x < w; ++x) {
      const double c = v[x];
      double acc = 0.0;
      if (k.kind == Kind::Odd)
        for (int i = 1; i <= r; ++i) acc += k.w[size_t(i - 1)] * (v[x - i] - v[x + i]);
      else
        for (int i = 1; i <= r; ++i) acc += k.w[size_t(i - 1)] * ((v[x + i] - c) + (v[x - i] - c));
      dst[x] = k.kind == Kind::Smooth ? c + acc : acc;
    }
  }
  return out;
}

Plane pass_y(const Plane& in, const Image& im, const Kernel& k) {
  const int r = int(k.w.size()), h = int(im.height);
  Plane out(in.size(), 0.0);
  for (int y = 0; y < h; ++y) {
    const double* c = &in[im.at(0, uint32_t(y))];
    double* dst = &out[im.at(0, uint32_t(y))];
    for (int i = 1; i <= r; ++i) {
      const double wi = k.w[size_t(i - 1)];
      const double* up = &in[im.at(0, uint32_t(std::min(y + i, h - 1)))];
      const double* down = &in[im.at(0, uint32_t(std::max(y - i, 0)))];
      if (k.kind == Kind::Odd)
        for (uint32_t x = 0; x < im.width; ++x) dst[x] += wi * (down[x] - up[x]);
      else
        for (uint32_t x = 0; x < im.width; ++x) dst[x] += wi * ((up[x] - c[x]) + (down[x] - c[x]));
    }
    if (k.kind == Kind::Smooth)
      for (uint32_t x = 0; x < im.width; ++x) dst[x] += c[x];
  }
  return out;
}

// Colour pipeline, spatial filtering: each opponent channel's contrast sensitivity function is
// a sum of Gaussians in frequency, S(f) = a1 exp(-b1 f^2) + a2 exp(-b2 f^2) (f in cycles per
// degree), whose spatial kernel is a1 sqrt(pi/b1) exp(-pi^2 x^2/b1) + a2 sqrt(pi/b2)
// exp(-pi^2 x^2/b2) (x in degrees, x = pixels / pixels_per_degree), normalized to sum 1 so a flat
// field keeps its colour. The paper's parameters:
//   achromatic (Y):   a1 1,    b1 0.0047, a2 0
//   red-green  (Cx):  a1 1,    b1 0.0053, a2 0
//   blue-yellow (Cz): a1 34.1, b1 0.04,   a2 13.5, b2 0.025
// The kernel spans radius ceil(3 sqrt(b_max / (2 pi^2)) ppd) pixels, b_max = 0.04 the widest
// (three standard deviations of the widest Gaussian), the same for all channels.
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kCsfAchromatic{1.0, 0.0047, 0.0, 0.0}, kCsfRedGreen{1.0, 0.0053, 0.0, 0.0},
    kCsfBlueYellow{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfMaxB = 0.04;

int csf_radius(double ppd) { return int(std::ceil(3.0 * std::sqrt(kCsfMaxB / (2.0 * kPi * kPi)) * ppd)); }

// exp(-pi^2 (i/ppd)^2 / b) for i = 0..r, and its sum over -r..r.
struct Gauss {
  std::vector<double> g;
  double sum = 0.0;
};
Gauss csf_gauss(double b, double ppd, int r) {
  Gauss G;
  for (int i = 0; i <= r; ++i) {
    const double x = double(i) / ppd;
    G.g.push_back(std::exp(-kPi * kPi * x * x / b));
    G.sum += (i == 0 ? 1.0 : 2.0) * G.g.back();
  }
  return G;
}

Kernel smooth_kernel(const Gauss& G) {
  Kernel k{Kind::Smooth, {}};
  for (size_t i = 1; i < G.g.size(); ++i) k.w.push_back(G.g[i] / G.sum);
  return k;
}

// The 2-D kernel of one CSF applied as separable passes. One Gaussian: its normalized 1-D
// kernel along x then y. Two Gaussians (blue-yellow): each term's 2-D weight is
// a sqrt(pi/b) G(x) G(y), summing to a sqrt(pi/b) S^2 with S the 1-D sum, so the normalized
// kernel is beta1 (g1 x g1) + beta2 (g2 x g2) with g = G/S and beta_k = a_k sqrt(pi/b_k) S_k^2 /
// (sum of both); written P1 + beta2 (P2 - P1), a flat field stays exactly flat.
struct CsfFilter {
  Kernel k1, k2;
  double beta2 = 0.0;
};
CsfFilter csf_filter(const Csf& c, double ppd, int r) {
  const Gauss g1 = csf_gauss(c.b1, ppd, r);
  CsfFilter f{smooth_kernel(g1), {}, 0.0};
  if (c.a2 > 0.0) {
    const Gauss g2 = csf_gauss(c.b2, ppd, r);
    f.k2 = smooth_kernel(g2);
    const double t1 = c.a1 * std::sqrt(kPi / c.b1) * g1.sum * g1.sum, t2 = c.a2 * std::sqrt(kPi / c.b2) * g2.sum * g2.sum;
    f.beta2 = t2 / (t1 + t2);
  }
  return f;
}

Plane apply_csf(const Plane& in, const Image& im, const CsfFilter& f) {
  Plane p1 = pass_y(pass_x(in, im, f.k1), im, f.k1);
  if (f.beta2 == 0.0) return p1;
  const Plane p2 = pass_y(pass_x(in, im, f.k2), im, f.k2);
  for (size_t i = 0; i < p1.size(); ++i) p1[i] += f.beta2 * (p2[i] - p1[i]);
  return p1;
}

// Feature pipeline: edges and points of the achromatic channel, found with the first and
// second derivatives of a Gaussian whose standard deviation is half of w = 0.082 degrees (the
// peak-to-trough width of the human edge detector the paper cites), sd = 0.5 w ppd pixels,
// over radius ceil(3 sd). In 2-D the edge kernel along x is -x g(x) g(y) and the point kernel
// (x^2/sd^2 - 1) g(x) g(y), each normalized so its positive weights sum to 1 and its negative
// weights to -1; the same kernels transposed give the y responses. As g(y) > 0, the signs are
// those of the x factor, so the normalized 2-D kernel is the 1-D x factor normalized that way
// times g normalized to sum 1: separable exactly.
constexpr double kFeatureWidth = 0.082;
struct FeatureFilters {
  Kernel smooth, edge, point;
};
FeatureFilters feature_filters(double ppd) {
  const double sd = 0.5 * kFeatureWidth * ppd;
  const int r = int(std::ceil(3.0 * sd));
  FeatureFilters f{{Kind::Smooth, {}}, {Kind::Odd, {}}, {Kind::ZeroSum, {}}};
  std::vector<double> g, point;
  double g_sum = 0.0, edge_positive = 0.0, point_positive = 0.0, point_negative = 0.0;
  for (int i = 0; i <= r; ++i) {
    const double x = double(i), gi = std::exp(-x * x / (2.0 * sd * sd)), pi = (x * x / (sd * sd) - 1.0) * gi;
    const double copies = i == 0 ? 1.0 : 2.0;
    g.push_back(gi);
    point.push_back(pi);
    g_sum += copies * gi;
    edge_positive += x * gi;  // -x g(x) is positive at x = -i only
    (pi > 0.0 ? point_positive : point_negative) += copies * std::abs(pi);
  }
  for (int i = 1; i <= r; ++i) {
    const size_t j = size_t(i);
    f.smooth.w.push_back(g[j] / g_sum);
    // Odd pass computes sum w_i (v[-i] - v[+i]): w_i is the (positive) weight at -i.
    f.edge.w.push_back(double(i) * g[j] / edge_positive);
    f.point.w.push_back(point[j] > 0.0 ? point[j] / point_positive : point[j] / point_negative);
  }
  return f;
}

// One image through both pipelines: the Hunt-adjusted L*a*b* of its CSF-filtered colours and
// the magnitudes of its edge and point responses.
struct Prepared {
  std::vector<Rgb> lab;
  Plane edge, point;
};

Prepared prepare(const std::vector<Rgb>& rgb, const Image& im, const CsfFilter (&csf)[3], const FeatureFilters& ff) {
  const size_t n = rgb.size();
  Plane chan[3], luminance(n);
  for (Plane& c : chan) c.resize(n);
  for (size_t p = 0; p < n; ++p) {
    const Rgb o = linear_rgb_to_ycxcz(rgb[p]);
    for (int c = 0; c < 3; ++c) chan[c][p] = o[size_t(c)];
    // Feature pipeline: the achromatic channel normalized to [0, 1], (Y + 16) / 116 = Y / Yn
    // (the paper's erratum corrects "division by 100" to 116), unfiltered.
    luminance[p] = (o[0] + 16.0) / 116.0;
  }
  for (int c = 0; c < 3; ++c) chan[c] = apply_csf(chan[c], im, csf[c]);

  Prepared out;
  out.lab.resize(n);
  for (size_t p = 0; p < n; ++p) {
    // Colour pipeline: back to linear RGB and clamped to the unit cube, since filtering can
    // leave the gamut, before L*a*b*.
    Rgb filtered = ycxcz_to_linear_rgb({chan[0][p], chan[1][p], chan[2][p]});
    for (double& v : filtered) v = std::clamp(v, 0.0, 1.0);
    out.lab[p] = hunt_lab(filtered);
  }

  const Plane smooth_y = pass_y(luminance, im, ff.smooth), smooth_x = pass_x(luminance, im, ff.smooth);
  const Plane ex = pass_x(smooth_y, im, ff.edge), px = pass_x(smooth_y, im, ff.point);
  const Plane ey = pass_y(smooth_x, im, ff.edge), py = pass_y(smooth_x, im, ff.point);
  out.edge.resize(n);
  out.point.resize(n);
  for (size_t p = 0; p < n; ++p) {
    out.edge[p] = std::sqrt(ex[p] * ex[p] + ey[p] * ey[p]);  // each in [-1, 1]
    out.point[p] = std::sqrt(px[p] * px[p] + py[p] * py[p]);
  }
  return out;
}

}  // namespace

FlipResult flip(const std::vector<float>& test, const std::vector<float>& reference, uint32_t width, uint32_t height,
                uint32_t stride, double pixels_per_degree) {
  if (width == 0 || height == 0) throw std::invalid_argument("flip: the image is empty");
  if (stride < 3) throw std::invalid_argument("flip: a pixel needs at least three channels (RGB)");
  const size_t pixels = size_t(width) * height;
  if (test.size() != pixels * stride || reference.size() != pixels * stride)
    throw std::invalid_argument("flip: an image's size is not width x height x stride");
  if (!std::isfinite(pixels_per_degree) || !(pixels_per_degree > 0.0))
    throw std::invalid_argument("flip: pixels_per_degree must be finite and positive");

  FlipResult result;
  std::vector<Rgb> t(pixels), r(pixels);
  std::vector<bool> bad(pixels, false);
  for (size_t p = 0; p < pixels; ++p) {
    bool t_ok = true, r_ok = true;
    for (size_t c = 0; c < 3; ++c) {
      const double a = test[p * stride + c], b = reference[p * stride + c];
      t_ok = t_ok && std::isfinite(a);
      r_ok = r_ok && std::isfinite(b);
      t[p][c] = std::clamp(a, 0.0, 1.0);
      r[p][c] = std::clamp(b, 0.0, 1.0);
    }
    if (t_ok && r_ok) continue;
    bad[p] = true;
    ++result.non_finite;
    if (!t_ok && !r_ok) t[p] = r[p] = Rgb{0.0, 0.0, 0.0};
    else if (!t_ok) t[p] = r[p];
    else r[p] = t[p];
  }

  const Image im{width, height};
  const int radius = csf_radius(pixels_per_degree);
  const CsfFilter csf[3] = {csf_filter(kCsfAchromatic, pixels_per_degree, radius),
                            csf_filter(kCsfRedGreen, pixels_per_degree, radius),
                            csf_filter(kCsfBlueYellow, pixels_per_degree, radius)};
  const FeatureFilters ff = feature_filters(pixels_per_degree);
  const Prepared pt = prepare(t, im, csf, ff), pr = prepare(r, im, csf, ff);

  // Feature pipeline, feature metric: the larger of the edge and point differences, scaled by
  // 1/sqrt(2) into [0, 1] (each response's magnitude is at most sqrt(2) for luminance in
  // [0, 1]), raised to qf = 0.5.
  constexpr double kQf = 0.5;
  result.map.resize(pixels);
  double sum = 0.0;
  size_t counted = 0;
  for (size_t p = 0; p < pixels; ++p) {
    if (bad[p]) {
      result.map[p] = std::numeric_limits<float>::quiet_NaN();
      continue;
    }
    const double color = remap_color(std::pow(hyab(pt.lab[p], pr.lab[p]), kQc));
    const double feature_difference =
        std::max(std::abs(pt.edge[p] - pr.edge[p]), std::abs(pt.point[p] - pr.point[p])) / std::numbers::sqrt2;
    const double feature = std::pow(feature_difference, kQf);
    // Final difference: colour^(1 - feature), so where an edge or a point differs, the colour
    // difference is raised towards 1; where features agree it is the colour difference.
    const double e = std::pow(color, 1.0 - feature);
    result.map[p] = float(e);
    sum += e;
    result.max = std::max(result.max, e);
    ++counted;
  }
  if (counted > 0) result.mean = sum / double(counted);
  return result;
}

}  // namespace prismoid::reference
