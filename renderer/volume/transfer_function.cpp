#include "renderer/volume/transfer_function.hpp"

#include <algorithm>
#include <cmath>

#include "scene/input_error.hpp"

namespace prismoid::volume {

namespace {

// Colour maps are published as sRGB display values; rendering works in linear RGB.
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

TransferFunction from_srgb(std::string name, std::initializer_list<std::pair<double, glm::dvec3>> points) {
  TransferFunction tf;
  tf.name = std::move(name);
  for (const auto& [x, c] : points)
    tf.color.push_back({x, glm::dvec3(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b))});
  tf.opacity = {{0.0, 0.0}, {1.0, 1.0}};
  return tf;
}

template <typename Point, typename Get>
double interpolate(const std::vector<Point>& points, double x, Get get) {
  if (x <= points.front().x) return get(points.front());
  if (x >= points.back().x) return get(points.back());
  const auto hi = std::upper_bound(points.begin(), points.end(), x, [](double v, const Point& p) { return v < p.x; });
  const auto lo = hi - 1;
  const double span = hi->x - lo->x;
  if (!(span > 0.0)) return get(*hi);
  const double w = (x - lo->x) / span;
  return (1.0 - w) * get(*lo) + w * get(*hi);
}

}  // namespace

double normalized(const TransferFunction& tf, double scalar) { return (scalar - tf.range_lo) / (tf.range_hi - tf.range_lo); }

std::vector<TfSample> breakpoints(const TransferFunction& tf) {
  std::vector<double> xs{0.0, 1.0};
  for (const auto& p : tf.color) xs.push_back(std::clamp(p.x, 0.0, 1.0));
  for (const auto& p : tf.opacity) xs.push_back(std::clamp(p.x, 0.0, 1.0));
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::vector<TfSample> samples;
  samples.reserve(xs.size());
  for (double x : xs) {
    TfSample s;
    s.x = x;
    for (int c = 0; c < 3; ++c) s.rgb[c] = interpolate(tf.color, x, [c](const ColorPoint& p) { return p.rgb[c]; });
    s.sigma = tf.density_scale * interpolate(tf.opacity, x, [](const OpacityPoint& p) { return p.opacity; });
    samples.push_back(s);
  }
  return samples;
}

TfSample evaluate(const std::vector<TfSample>& samples, double x) {
  x = std::clamp(x, 0.0, 1.0);
  TfSample s;
  s.x = x;
  for (int c = 0; c < 3; ++c) s.rgb[c] = interpolate(samples, x, [c](const TfSample& p) { return p.rgb[c]; });
  s.sigma = interpolate(samples, x, [](const TfSample& p) { return p.sigma; });
  return s;
}

void validate(const TransferFunction& tf) {
  const std::string src = tf.name.empty() ? std::string("transfer function") : tf.name;
  if (tf.color.empty()) throw InputError(src, "has no colour points");
  if (tf.opacity.empty()) throw InputError(src, "has no opacity points");
  auto in_unit = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
  for (size_t i = 0; i < tf.color.size(); ++i) {
    const auto& p = tf.color[i];
    if (!std::isfinite(p.x) || (i > 0 && p.x < tf.color[i - 1].x))
      throw InputError(src, "colour point " + std::to_string(i) + " is not finite or not sorted by position");
    if (!in_unit(p.rgb.r) || !in_unit(p.rgb.g) || !in_unit(p.rgb.b))
      throw InputError(src, "colour point " + std::to_string(i) + " has a component outside [0, 1]");
  }
  for (size_t i = 0; i < tf.opacity.size(); ++i) {
    const auto& p = tf.opacity[i];
    if (!std::isfinite(p.x) || (i > 0 && p.x < tf.opacity[i - 1].x))
      throw InputError(src, "opacity point " + std::to_string(i) + " is not finite or not sorted by position");
    if (!in_unit(p.opacity)) throw InputError(src, "opacity point " + std::to_string(i) + " is outside [0, 1]");
  }
  if (!std::isfinite(tf.range_lo) || !std::isfinite(tf.range_hi) || !(tf.range_hi > tf.range_lo))
    throw InputError(src, "scalar range [" + std::to_string(tf.range_lo) + ", " + std::to_string(tf.range_hi) + "] is empty");
  if (!std::isfinite(tf.density_scale) || tf.density_scale < 0.0) throw InputError(src, "density scale must be finite and >= 0");
}

std::vector<std::string> preset_names() { return {"cool-to-warm", "viridis", "grayscale", "black-body"}; }

TransferFunction preset(const std::string& name) {
  if (name == "cool-to-warm")  // ParaView's default (Moreland 2009), interpolated here in linear RGB
    return from_srgb(name, {{0.0, {0.231373, 0.298039, 0.752941}}, {0.5, {0.865003, 0.865003, 0.865003}},
                            {1.0, {0.705882, 0.0156863, 0.14902}}});
  if (name == "viridis")  // matplotlib's viridis sampled every 32 entries of its 256
    return from_srgb(name, {{0.0, {0.267004, 0.004874, 0.329415}},
                            {0.125, {0.282623, 0.140926, 0.457517}},
                            {0.25, {0.253935, 0.265254, 0.529983}},
                            {0.375, {0.206756, 0.371758, 0.553117}},
                            {0.5, {0.163625, 0.471133, 0.558148}},
                            {0.625, {0.127568, 0.566949, 0.550556}},
                            {0.75, {0.134692, 0.658636, 0.517649}},
                            {0.875, {0.266941, 0.748751, 0.440573}},
                            {1.0, {0.993248, 0.906157, 0.143936}}});
  if (name == "grayscale") return from_srgb(name, {{0.0, {0.0, 0.0, 0.0}}, {1.0, {1.0, 1.0, 1.0}}});
  if (name == "black-body")  // ParaView's "Black-Body Radiation" control colours
    return from_srgb(name, {{0.0, {0.0, 0.0, 0.0}}, {0.39, {0.901961, 0.0, 0.0}}, {0.58, {0.901961, 0.901961, 0.0}},
                            {1.0, {1.0, 1.0, 1.0}}});
  std::string names;
  for (const auto& n : preset_names()) names += (names.empty() ? "" : ", ") + n;
  throw InputError(name, "is neither a transfer-function preset (" + names + ") nor a file");
}

}  // namespace prismoid::volume
