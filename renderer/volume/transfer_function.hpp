#pragma once
// Transfer functions: a scalar field's value -> colour and extinction, for emission-absorption.
// VTK's vocabulary: a colour map and a scalar opacity function over a data range. Both are
// piecewise linear in the normalized scalar x = (s - range_lo) / (range_hi - range_lo), and
// constant beyond [0, 1] (values outside the range clamp, as in ParaView).
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace prismoid::volume {

struct ColorPoint {
  double x;
  glm::dvec3 rgb;  // linear RGB in [0, 1]
};
struct OpacityPoint {
  double x;
  double opacity;  // in [0, 1]; extinction = density_scale * opacity
};

struct TransferFunction {
  std::string name;
  std::vector<ColorPoint> color;      // sorted by x; at least one point
  std::vector<OpacityPoint> opacity;  // sorted by x; at least one point
  double range_lo = 0.0;              // scalar mapped to x = 0
  double range_hi = 1.0;              // scalar mapped to x = 1 (> range_lo)
  double density_scale = 1.0;         // extinction (1/length) at opacity 1
};

// Colour and extinction at one x.
struct TfSample {
  double x = 0.0;
  glm::dvec3 rgb{0.0};
  double sigma = 0.0;
};

// The scalar's position in the range (not clamped).
double normalized(const TransferFunction& tf, double scalar);

// The transfer function as one piecewise-linear function of x on [0, 1]: the union of the
// colour and opacity points, plus x = 0 and x = 1, sorted, each with both values. Between
// consecutive samples colour and extinction are exactly linear.
std::vector<TfSample> breakpoints(const TransferFunction& tf);

// Value at x (clamped into [0, 1]) of the piecewise-linear function `samples` describes.
TfSample evaluate(const std::vector<TfSample>& samples, double x);

// Throws InputError(tf.name, ...) for an empty list, unsorted or non-finite points, colours or
// opacities outside [0, 1], an empty range, a negative density scale.
void validate(const TransferFunction& tf);

// Named presets over [0, 1] with an opacity ramp from 0 to 1; names: preset_names().
TransferFunction preset(const std::string& name);
std::vector<std::string> preset_names();

}  // namespace prismoid::volume
