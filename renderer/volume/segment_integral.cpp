#include "renderer/volume/segment_integral.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace prismoid::volume {

namespace {

// Gauss-Legendre nodes and weights on [-1, 1], 8 points (the 4 positive nodes; symmetric).
constexpr std::array<double, 4> kNodes = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
constexpr std::array<double, 4> kWeights = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

// integral_a^b exp(-(s0 t + k t^2)) dt by Gauss-Legendre.
double gauss_exp(double s0, double k, double a, double b) {
  const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
  double sum = 0.0;
  for (size_t i = 0; i < kNodes.size(); ++i)
    for (double sign : {-1.0, 1.0}) {
      const double t = mid + sign * half * kNodes[i];
      sum += kWeights[i] * std::exp(-(s0 * t + k * t * t));
    }
  return sum * half;
}

// integral_0^h exp(-tau(t)) dt with tau(t) = s0 t + k t^2 (s0 >= 0, s0 + 2 k h >= 0: sigma is
// non-negative on the piece). Sub-pieces end where tau reaches multiples of 1/2; past tau = 40
// the rest contributes under e^-40 of the whole and is taken in one piece.
double integral_of_transmittance(double s0, double k, double h) {
  const double tau_h = s0 * h + k * h * h;
  if (!(tau_h > 0.0)) return h;
  double sum = 0.0, t_prev = 0.0;
  const int steps = static_cast<int>(std::min(std::ceil(tau_h / 0.5), 80.0));
  for (int i = 1; i <= steps; ++i) {
    double t = h;
    if (i < steps) {
      const double y = 0.5 * i;  // solve k t^2 + s0 t = y, in the form without cancellation
      t = 2.0 * y / (s0 + std::sqrt(std::max(s0 * s0 + 4.0 * k * y, 0.0)));
      t = std::clamp(t, t_prev, h);
    }
    sum += gauss_exp(s0, k, t_prev, t);
    t_prev = t;
  }
  return sum;
}

// One piece of length h on which sigma and colour are linear: from (sigma0, c0) to (sigma1, c1).
SegmentRadiance integrate_piece(double h, double sigma0, double sigma1, const glm::dvec3& c0, const glm::dvec3& c1) {
  SegmentRadiance r;
  if (!(h > 0.0)) return r;
  const double k = 0.5 * (sigma1 - sigma0) / h;
  const double tau_h = 0.5 * (sigma0 + sigma1) * h;
  const double transmittance = std::exp(-tau_h);
  const double mean_transmittance = integral_of_transmittance(sigma0, k, h) / h;
  // Integration by parts of sigma e^-tau = -(e^-tau)'.
  r.color = c0 - c1 * transmittance + (c1 - c0) * mean_transmittance;
  r.alpha = -std::expm1(-tau_h);
  return r;
}

}  // namespace

SegmentRadiance composite(const SegmentRadiance& front, const SegmentRadiance& behind) {
  const double t = 1.0 - front.alpha;
  return {front.color + t * behind.color, front.alpha + t * behind.alpha};
}

SegmentRadiance integrate_segment(const std::vector<TfSample>& tf, double x_front, double x_back, double length) {
  SegmentRadiance total;
  if (!(length > 0.0)) return total;
  // Parameters u in [0, 1] along the segment where x crosses a breakpoint.
  std::vector<double> cuts{0.0, 1.0};
  const double dx = x_back - x_front;
  if (dx != 0.0)
    for (const TfSample& s : tf) {
      const double u = (s.x - x_front) / dx;
      if (u > 0.0 && u < 1.0) cuts.push_back(u);
    }
  std::sort(cuts.begin(), cuts.end());
  TfSample a = evaluate(tf, x_front);
  for (size_t i = 1; i < cuts.size(); ++i) {
    const double u = cuts[i];
    const TfSample b = evaluate(tf, i + 1 == cuts.size() ? x_back : x_front + u * dx);
    total = composite(total, integrate_piece((u - cuts[i - 1]) * length, a.sigma, b.sigma, a.rgb, b.rgb));
    a = b;
  }
  return total;
}

PreintegrationTable build_preintegration_table(const std::vector<TfSample>& tf, uint32_t size, double max_length) {
  PreintegrationTable table;
  table.size = std::max(size, 2u);
  table.max_length = max_length;
  const uint32_t n = table.size;
  table.texels.resize(size_t(n) * n * n);
  for (uint32_t k = 0; k < n; ++k)
    for (uint32_t j = 0; j < n; ++j)
      for (uint32_t i = 0; i < n; ++i) {
        const SegmentRadiance r = integrate_segment(tf, double(i) / (n - 1), double(j) / (n - 1), double(k) / (n - 1) * max_length);
        table.texels[(size_t(k) * n + j) * n + i] = glm::vec4(glm::vec3(r.color), float(r.alpha));
      }
  return table;
}

SegmentRadiance lookup(const PreintegrationTable& table, double x_front, double x_back, double length) {
  const uint32_t n = table.size;
  const double scale = double(n - 1);
  const double coords[3] = {std::clamp(x_front, 0.0, 1.0) * scale, std::clamp(x_back, 0.0, 1.0) * scale,
                            table.max_length > 0.0 ? std::clamp(length / table.max_length, 0.0, 1.0) * scale : 0.0};
  uint32_t base[3];
  double frac[3];
  for (int a = 0; a < 3; ++a) {
    base[a] = std::min(static_cast<uint32_t>(coords[a]), n - 2);
    frac[a] = coords[a] - base[a];
  }
  glm::dvec4 sum(0.0);
  for (int corner = 0; corner < 8; ++corner) {
    double w = 1.0;
    uint32_t idx[3];
    for (int a = 0; a < 3; ++a) {
      const bool up = (corner >> a) & 1;
      idx[a] = base[a] + (up ? 1u : 0u);
      w *= up ? frac[a] : 1.0 - frac[a];
    }
    sum += w * glm::dvec4(table.texels[(size_t(idx[2]) * n + idx[1]) * n + idx[0]]);
  }
  return {glm::dvec3(sum), sum.w};
}

}  // namespace prismoid::volume
