#include "renderer/volume/cpu/reference_frame.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "renderer/reference/analytic_march.hpp"
#include "renderer/reference/emission_absorption.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

// A frame of `size` for a CPU reference to fill: one quantity and one RGBA display value per pixel.
OffscreenFrame blank_frame(VkExtent2D size) {
  OffscreenFrame f;
  f.width = size.width;
  f.height = size.height;
  f.quantity.resize(size_t(size.width) * size.height);
  f.display.resize(f.quantity.size() * 4);
  return f;
}

// The CPU double-precision reference, resolved the way the GPU's resolve pass does it.
OffscreenFrame render_reference(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                       VkExtent2D size) {
  const auto start = std::chrono::steady_clock::now();
  OffscreenFrame f = blank_frame(size);
  const size_t pixels = f.quantity.size();
  const std::vector<float>* limit = resolve.depth_limit.get();  // rays end at opaque geometry
  if (limit && limit->size() != pixels)
    throw InputError("depth limit", "has " + std::to_string(limit->size()) + " values for a " + std::to_string(size.width) + "x" +
                                        std::to_string(size.height) + " frame");
  if (resolve.quantity == volume::Quantity::Color) {
    const auto image =
        reference::emission_absorption_image(mesh, resolve.transfer, camera, size.width, size.height, 0.0, 0.0, nullptr, nullptr, limit);
    f.emission.resize(pixels * 4);
    for (size_t i = 0; i < pixels; ++i) {
      const glm::dvec4 c = image.pixels[i];
      const double transmittance = 1.0 - c.a;
      f.quantity[i] = float(transmittance);
      const glm::dvec3 shown = glm::dvec3(c) + transmittance * glm::dvec3(resolve.background);
      for (int k = 0; k < 3; ++k) f.display[4 * i + k] = float(shown[k]);
      f.display[4 * i + 3] = 1.0f;
      for (int k = 0; k < 4; ++k) f.emission[4 * i + k] = float(c[k]);
    }
    f.report.ordering = "exact (per pixel, CPU)";
  } else {
    const std::vector<double> tau = reference::optical_depth_image(mesh, camera, size.width, size.height, 0.0, 0.0, nullptr, limit);
    for (size_t i = 0; i < pixels; ++i) {
      const double t = std::exp(-tau[i]);
      f.quantity[i] = float(resolve.quantity == volume::Quantity::Transmittance ? t : tau[i]);
      const glm::dvec3 c = glm::mix(glm::dvec3(resolve.medium), glm::dvec3(resolve.background), t);
      for (int k = 0; k < 3; ++k) f.display[4 * i + k] = float(c[k]);
      f.display[4 * i + 3] = 1.0f;
    }
    f.report.ordering = "none (order-independent)";
  }
  f.report.order_exact = true;
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  f.passes.push_back({"reference (CPU, double)", ms});
  return f;
}

// The CPU reference of an analytic field (what interval-march approximates): optical depth by
// fine Gauss-Legendre panels, colour and isosurfaces by marching
// in steps of 1/2000 of the bounds' diagonal, resolved as the GPU does.
OffscreenFrame render_field_reference(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                             VkExtent2D size) {
  if (resolve.depth_limit) throw InputError("depth limit", "is not followed when marching a field or drawing an isosurface");
  const auto start = std::chrono::steady_clock::now();
  const volume::MarchSettings& m = resolve.march;
  const Bounds b = bounds_of(mesh);
  const double fine_step = glm::length(b.max - b.min) / 2000.0;
  OffscreenFrame f = blank_frame(size);
  const size_t pixels = f.quantity.size();
  auto put = [&](size_t i, const glm::dvec3& c) {
    for (int k = 0; k < 3; ++k) f.display[4 * i + k] = float(c[k]);
    f.display[4 * i + 3] = 1.0f;
  };
  if (resolve.quantity == volume::Quantity::Color) {
    const auto image = reference::field_color_image(mesh, m.field, resolve.transfer, camera, size.width, size.height, fine_step);
    f.emission.resize(pixels * 4);
    for (size_t i = 0; i < pixels; ++i) {
      const glm::dvec4 c = image.pixels[i];
      f.quantity[i] = float(1.0 - c.a);
      put(i, glm::dvec3(c) + (1.0 - c.a) * glm::dvec3(resolve.background));
      for (int k = 0; k < 4; ++k) f.emission[4 * i + k] = float(c[k]);
    }
  } else if (resolve.quantity == volume::Quantity::Isosurface) {
    const auto image = reference::isosurface_image(mesh, m.field, m.isovalue, camera, size.width, size.height, fine_step);
    f.emission.resize(pixels * 4);
    for (size_t i = 0; i < pixels; ++i) {
      f.quantity[i] = float(image.distance[i]);
      put(i, image.distance[i] > 0.0 ? glm::dvec3(image.shade[i]) : glm::dvec3(resolve.background));
      for (int k = 0; k < 3; ++k) f.emission[4 * i + k] = float(image.shade[i]);
      f.emission[4 * i + 3] = float(image.distance[i]);
    }
  } else {
    const auto tau = reference::field_optical_depth_image(mesh, m.field, m.density_scale, camera, size.width, size.height);
    for (size_t i = 0; i < pixels; ++i) {
      const double t = std::exp(-tau[i]);
      f.quantity[i] = float(resolve.quantity == volume::Quantity::Transmittance ? t : tau[i]);
      put(i, glm::mix(glm::dvec3(resolve.medium), glm::dvec3(resolve.background), t));
    }
  }
  f.report.ordering = "exact (per pixel, CPU)";
  f.report.order_exact = true;
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  f.passes.push_back({"reference (CPU, double, analytic field)", ms});
  return f;
}

OffscreenFrame reference_of(const TetMesh& mesh, const Camera& camera, const volume::ResolveSettings& resolve,
                                   VkExtent2D size, bool field) {
  return field ? render_field_reference(mesh, camera, resolve, size) : render_reference(mesh, camera, resolve, size);
}

double error_peak(const OffscreenFrame& ref, volume::Quantity q) {
  if (q != volume::Quantity::OpticalDepth) return 1.0;
  double peak = 0.0;
  for (float v : ref.quantity)
    if (std::isfinite(v)) peak = std::max(peak, double(v));
  return peak;
}

reference::ImageError frame_error(const OffscreenFrame& test, const OffscreenFrame& ref, volume::Quantity q) {
  if (q == volume::Quantity::Color) return reference::image_error(test.display, ref.display, 1.0, 4, 3);
  return reference::image_error(test.quantity, ref.quantity, error_peak(ref, q), 1, 1);
}

}  // namespace prismoid::frame
