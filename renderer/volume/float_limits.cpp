#include "renderer/volume/float_limits.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {

namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// The rounding of x to float, as a double.
double float_rounding(double x) { return std::abs(double(float(x)) - x); }

// The largest magnitude the GPU's projected (NDC) coordinates may reach, 2^60: areas of
// projected faces are products of two such coordinates and stay below float's 2^128.
constexpr double kNdcLimit = 1.152921504606846976e18;
// The farthest distance from the eye the GPU works with, 2^100: 1/depth and products of
// depths with ray slopes stay normal floats.
constexpr double kDepthLimit = 1.2676506002282294e30;
// float32's smallest normal number: a scale below it is flushed or loses its bits.
constexpr double kFloatMinNormal = 1.1754943508222875e-38;

}  // namespace

MeshFloatFacts float_facts(const TetMesh& mesh) {
  MeshFloatFacts f;
  f.name = mesh.name;
  f.bounds = bounds_of(mesh);
  f.origin = f.bounds.center();
  f.diagonal = glm::length(f.bounds.max - f.bounds.min);
  for (double s : mesh.cell_extinction) f.max_extinction = std::max(f.max_extinction, s);
  for (double s : mesh.point_extinction) f.max_extinction = std::max(f.max_extinction, s);
  for (const auto& p : mesh.points) {
    const glm::dvec3 r = p - f.origin;
    f.position_rounding = std::max({f.position_rounding, float_rounding(r.x), float_rounding(r.y), float_rounding(r.z)});
  }
  for (const auto* field : {&mesh.point_scalars, &mesh.cell_scalars})
    for (double s : *field) f.scalar_abs_max = std::max(f.scalar_abs_max, std::abs(s));
  f.has_scalars = !mesh.point_scalars.empty() || !mesh.cell_scalars.empty();
  return f;
}

double extinction_cap(double diagonal) { return kSumMargin * kFloatMax / std::max(diagonal, 1.0); }

ScalarMapping scalar_mapping(const TransferFunction& tf) {
  // Halves first: hi - lo overflows double for a range like -1e308,1e308.
  const double half_width = 0.5 * tf.range_hi - 0.5 * tf.range_lo;
  return {0.5 / half_width, -(0.5 * tf.range_lo) / half_width};
}

namespace {

// How far the GPU's camera-space position of p strays from the exact one, across the view (x)
// and along it (y): p rounded to float relative to the origin, the float view matrix, and the
// transform's products and sums in float, unfused and fused (drivers may contract either way).
glm::dvec2 transform_error(const glm::dmat4& view, const glm::dvec3& local) {
  const glm::mat4 view_f(view);
  const glm::vec3 p(local);
  glm::dvec2 worst(0.0);
  for (int row = 0; row < 3; ++row) {
    const double exact = view[0][row] * local.x + view[1][row] * local.y + view[2][row] * local.z + view[3][row];
    const float unfused = ((view_f[0][row] * p.x + view_f[1][row] * p.y) + view_f[2][row] * p.z) + view_f[3][row];
    const float fused = std::fma(view_f[2][row], p.z, std::fma(view_f[1][row], p.y, view_f[0][row] * p.x)) + view_f[3][row];
    const double e = std::max(std::abs(double(unfused) - exact), std::abs(double(fused) - exact));
    (row < 2 ? worst.x : worst.y) = std::max(row < 2 ? worst.x : worst.y, e);
  }
  return worst;
}

}  // namespace

FloatCheck check_float_limits(const MeshFloatFacts& mesh, const Camera& camera, uint32_t width, uint32_t height,
                              const ResolveSettings& settings, bool gpu, const std::vector<glm::dvec3>* points) {
  validate(camera);
  FloatCheck check;
  const std::string& name = mesh.name.empty() ? std::string("(unnamed mesh)") : mesh.name;
  const double margin_max = kSumMargin * kFloatMax;

  // The image: optical depth is stored as float32 (and summed in it on the GPU).
  if (settings.quantity == Quantity::OpticalDepth) {
    // Marched: the field's largest value at the mesh's points (a field mesh's extinction holds it
    // at the points and centroids already scaled).
    const double sigma = settings.march.enabled ? std::max(mesh.max_extinction, settings.march.density_scale * mesh.scalar_abs_max)
                                                : mesh.max_extinction;
    if (sigma * mesh.diagonal > margin_max)
      throw InputError(name, "optical depths up to " + number(sigma * mesh.diagonal) + " (extinction up to " + number(sigma / mesh.unit) +
                                 " over the data's diagonal " + number(mesh.diagonal * mesh.unit) + ") exceed " + number(margin_max) +
                                 ", float32's largest value less a 2^16 margin for the sums along a ray; scale the "
                                 "extinction down (" + setting("density-scale") + ") or ask for " + setting("quantity", "transmittance"));
  }
  // A camera that sees none of the data: every corner of the bounds behind the near plane (an
  // all-background image was written without a word for `--near 100`).
  if (mesh.diagonal > 0.0) {
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    double farthest = -1e300;
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 p((corner & 1) ? mesh.bounds.max.x : mesh.bounds.min.x, (corner & 2) ? mesh.bounds.max.y : mesh.bounds.min.y,
                         (corner & 4) ? mesh.bounds.max.z : mesh.bounds.min.z);
      farthest = std::max(farthest, glm::dot(p - camera.eye, forward));
    }
    if (farthest <= 0.0)
      check.warnings.push_back("camera: the data lie behind the eye (all of them at least " +
                               number(-farthest * mesh.unit) + " behind it along the view): the image shows none of them");
    else if (camera.near_distance >= farthest)
      check.warnings.push_back("camera: the near plane (" + setting("near", number(camera.near_distance * mesh.unit)) +
                               ") lies beyond the data's farthest depth along the view (" + number(farthest * mesh.unit) +
                               "): the image shows none of them");
  }
  if (!gpu) return check;

  // The camera: projected coordinates and depths within float's range.
  const double distance = std::max(glm::length(mesh.bounds.min - camera.eye), glm::length(mesh.bounds.max - camera.eye)) +
                          mesh.diagonal;  // bounds every point's distance from the eye
  if (!(distance < kDepthLimit))
    throw InputError("camera", "the data lie up to " + number(distance * mesh.unit) + " from the eye, " + number(distance) +
                               " times their own scale (" + number(mesh.unit) + "); the GPU's float32 depths and their "
                               "reciprocals stay exact only up to " + number(kDepthLimit) + " (2^100) times it: move the eye closer");
  const double aspect = double(width) / double(std::max(height, 1u));
  const double scale = std::max(1.0, 1.0 / aspect) / std::tan(glm::radians(camera.fovy_degrees) * 0.5);  // max(P00, P11)
  const double ndc = scale * distance / camera.near_distance;
  if (!(ndc < kNdcLimit))
    throw InputError("camera", setting("near", number(camera.near_distance * mesh.unit)) + " and " + setting("fovy", number(camera.fovy_degrees)) +
                               " project points up to " + number(distance * mesh.unit) + " away to screen coordinates up to " +
                               number(ndc) + "; the GPU's float32 projected areas need them below " + number(kNdcLimit) +
                               " (2^60): raise " + setting("near") + " or widen " + setting("fovy"));

  // The transfer function's input, stored and mapped in float.
  if (settings.quantity == Quantity::Color || (settings.march.enabled && settings.quantity != Quantity::OpticalDepth &&
                                               settings.quantity != Quantity::Isosurface)) {
    if (mesh.scalar_abs_max > kFloatMax)
      throw InputError(name, "has scalar values up to " + number(mesh.scalar_abs_max) +
                                 ", beyond float32's largest value " + number(kFloatMax) + " that the GPU stores them in");
    const ScalarMapping m = scalar_mapping(settings.transfer);
    const double reach = std::abs(m.scale) * mesh.scalar_abs_max + std::abs(m.offset);
    if (!(reach <= margin_max))
      throw InputError(setting("tf-range"), "maps the data (values up to " + number(mesh.scalar_abs_max) + " in magnitude) to x up to " +
                                         number(reach) + ", beyond float32's range less a 2^16 margin (" + number(margin_max) + ")");
    if (std::abs(m.scale) < kFloatMinNormal && std::abs(m.scale) * mesh.scalar_abs_max >= std::ldexp(1.0, -24))
      throw InputError(setting("tf-range"), "is so wide (" + number(settings.transfer.range_hi - settings.transfer.range_lo) +
                                         ") that 1 / width, " + number(m.scale) +
                                         ", is below float32's smallest normal number while it still moves the data's x by " +
                                         number(std::abs(m.scale) * mesh.scalar_abs_max));
    // x = s * scale + offset rounds by a few ulps of its terms.
    const double x_rounding = 4.0 * std::ldexp(1.0, -24) * reach;
    if (x_rounding > std::ldexp(1.0, -10))
      check.warnings.push_back(setting("tf-range") + ": the range is narrow next to the data's magnitude: float32 places each value in "
                               "the transfer function only to " + number(x_rounding) + " of the range");
  }

  // Positions: each point's camera-space position as the GPU computes it, across the view (its
  // rounding along the view only scales the image by a relative error).
  if (height > 0 && mesh.diagonal > 0.0) {
    const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
    const glm::dmat4 view = view_matrix(camera, mesh.origin);
    double nearest = 1e300;  // the nearest depth of the data's bounds (the near plane if it cuts them)
    for (int corner = 0; corner < 8; ++corner) {
      const glm::dvec3 p((corner & 1) ? mesh.bounds.max.x : mesh.bounds.min.x, (corner & 2) ? mesh.bounds.max.y : mesh.bounds.min.y,
                         (corner & 4) ? mesh.bounds.max.z : mesh.bounds.min.z);
      nearest = std::min(nearest, glm::dot(p - camera.eye, forward));
    }
    nearest = std::max(nearest, camera.near_distance);
    // An error at depth d (at least the near plane's, where clipping puts the nearest points) in
    // pixels: across the view over a pixel's width there, along it as the relative change of
    // scale it makes over half the image.
    const double pixel_per_depth = 2.0 * std::tan(glm::radians(camera.fovy_degrees) * 0.5) / double(height);
    auto in_pixels = [&](glm::dvec2 error, double depth) {
      depth = std::max(depth, camera.near_distance);
      return error.x / (pixel_per_depth * depth) + error.y / depth * 0.5 * double(std::max(width, height));
    };
    // A bound from the facts: the positions' rounding, the view's entries' rounding times the
    // data's extent and the translation, and a few ulps of the transform's terms.
    double rotation_rounding = 0.0;
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) rotation_rounding = std::max(rotation_rounding, float_rounding(view[col][row]));
    const double radius = 0.5 * mesh.diagonal, ulp = std::ldexp(1.0, -24);
    const double lateral_translation = std::max(std::abs(view[3][0]), std::abs(view[3][1]));
    glm::dvec2 error(mesh.position_rounding + std::max(float_rounding(view[3][0]), float_rounding(view[3][1])) +
                         3.0 * rotation_rounding * radius + 4.0 * ulp * (radius + lateral_translation),
                     mesh.position_rounding + float_rounding(view[3][2]) + 3.0 * rotation_rounding * radius +
                         4.0 * ulp * (radius + std::abs(view[3][2])));
    const double threshold = std::ldexp(1.0, -8);
    double pixels = in_pixels(error, nearest);
    if (pixels > threshold && points) {
      // What float actually does to each point, in pixels at its own depth; only points nearer
      // than where the bound itself drops below the threshold can exceed it.
      const glm::dvec2 bound = error;
      error = glm::dvec2(0.0);
      pixels = 0.0;
      for (const auto& p : *points) {
        const double depth = glm::dot(p - camera.eye, forward);
        if (in_pixels(bound, depth) <= threshold) continue;
        const glm::dvec2 e = transform_error(view, p - mesh.origin);
        const double px = in_pixels(e, depth);
        if (px > pixels) {
          pixels = px;
          error = e;
          nearest = std::max(glm::dot(p - camera.eye, forward), camera.near_distance);
        }
      }
    }
    if (pixels > threshold)
      check.warnings.push_back("the GPU's float32 positions (relative to the data's centre, " + number(radius * mesh.unit) +
                               " from its farthest corner) and camera place points only to " + number(error.x * mesh.unit) +
                               " world units across the view, " + number(pixels) + " pixels at depth " +
                               number(nearest * mesh.unit) + ", more than the rasterizer's 2^-8 pixel: the image is only that precise");
  }
  return check;
}

}  // namespace prismoid::volume
