#pragma once
// Emission-absorption along one straight segment, in double precision: the exact integral that
// the CPU reference composites and that the pre-integration table samples.
//
// Model (Max 1995, "Optical models for direct volume rendering"): along the segment from its
// front (t = 0, nearest the eye) to its back (t = L), extinction sigma(t) and colour c(t) come
// from the transfer function of a scalar that is linear in t (x_front to x_back). Light
// reaching the eye from the segment is
//     C = integral_0^L sigma(t) c(t) exp(-tau(t)) dt,   tau(t) = integral_0^t sigma,
// and the segment lets through T = exp(-tau(L)) of what lies behind it. alpha = 1 - T.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "renderer/volume/transfer_function.hpp"

namespace prismoid::volume {

struct SegmentRadiance {
  glm::dvec3 color{0.0};  // premultiplied: light the segment sends towards the eye
  double alpha = 0.0;     // 1 - transmittance
};

// Front-to-back compositing: `behind` seen through `front`.
SegmentRadiance composite(const SegmentRadiance& front, const SegmentRadiance& behind);

// The exact integral for a segment of `length` whose normalized scalar runs linearly from
// x_front to x_back (`tf` from breakpoints()). The segment is split where x crosses a
// breakpoint, so colour and extinction are linear in t on each piece; there
//   integral sigma c e^-tau dt = c0 - c1 e^-tau(h) + (c1 - c0)/h integral e^-tau dt,
// and the last integral (a Gaussian one) is done by 8-point Gauss-Legendre on sub-pieces
// over which tau grows by at most 1/2, which is accurate to double rounding.
SegmentRadiance integrate_segment(const std::vector<TfSample>& tf, double x_front, double x_back, double length);

// A table of integrate_segment over x_front, x_back in [0, 1] and length in [0, max_length],
// sampled at `size` points on each axis (ends included), for trilinear lookup on the GPU.
// Texel (i, j, k) holds (color, alpha) for x_front = i/(size-1), x_back = j/(size-1),
// length = k/(size-1) * max_length, at index (k * size + j) * size + i.
struct PreintegrationTable {
  uint32_t size = 0;
  double max_length = 0.0;
  std::vector<glm::vec4> texels;
};
PreintegrationTable build_preintegration_table(const std::vector<TfSample>& tf, uint32_t size, double max_length);

// The trilinear lookup the fragment shader does, in double (for measuring the table's error).
SegmentRadiance lookup(const PreintegrationTable& table, double x_front, double x_back, double length);

}  // namespace prismoid::volume
