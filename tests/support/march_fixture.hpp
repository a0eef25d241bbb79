#pragma once
// What the GPU march tests share: a camera looking at a point, and a fixture rendering one
// offscreen frame of interval-march through a field at a given step (cells in mesh order: the
// order-independent quantities these tests compare need no sort).
#include <cmath>
#include <cstdint>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/volume/analytic_field.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid::test {

constexpr double kUlp = 1.0 / 16777216.0;  // 2^-24, float's unit roundoff

inline Camera looking_from(const glm::dvec3& eye, const glm::dvec3& target = glm::dvec3(0.0), double fovy = 40.0) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = glm::dvec3(0, 1, 0);
  c.fovy_degrees = fovy;
  c.near_distance = 0.05;
  return c;
}

// On both interval backends (support/backends.hpp): TEST_P, and PRISMOID_ON_BOTH_BACKENDS.
class MarchTest : public GpuTest, public OnBackend {
 public:
  frame::OffscreenFrame render(const TetMesh& mesh, const volume::AnalyticField& field, volume::Quantity q, double step,
                               const Camera& camera, uint32_t w, uint32_t h, double isovalue = 0.5) {
    frame::FrameRenderer renderer(device(), mesh);
    frame::FrameSettings settings = settings_on_backend();
    settings.resolve.quantity = q;
    settings.resolve.march.enabled = true;
    settings.resolve.march.field = field;
    settings.resolve.march.step = step;
    settings.resolve.march.isovalue = isovalue;
    settings.ordering = frame::Ordering::MeshOrder;
    return renderer.render_offscreen(camera, settings, {w, h});
  }
  // What the mesh backend's snapping adds between a march and exact interval shading of the same
  // linear field. Both take the interval's depths from the same snapped proxies, but the exact
  // pass takes the field from the proxy's interpolated attributes, which belong to the proxy's
  // snapped position, while the march evaluates the field on the pixel's own ray: the two read
  // the field at points up to a subpixel step (2^-bits pixel, at least the half step a vertex
  // moves, along both axes) apart across the view. At depth at most `farthest` a pixel spans
  // 2 farthest tan(fovy / 2) / height, so over `length` of ray the optical depths differ by at
  // most length * |gradient| * that span * 2^-bits. Measured on the H200 (which interpolates
  // from snapped positions; lavapipe agreed to float rounding): up to 2.6e-5 where the float
  // terms alone allowed 9.8e-6. The compute backend finds each interval on the pixel's own
  // ray: nothing snaps, nothing is added.
  double snapped_field_tolerance(const Camera& camera, uint32_t height, double gradient, double farthest, double length) const {
    if (compute()) return 0.0;
    const double pixel = 2.0 * farthest * std::tan(camera.fovy_degrees * M_PI / 360.0) / height;
    return length * gradient * pixel * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
  }

  // The same mesh's optical depth by exact interval shading of its point extinction (what a
  // march of a linear field must reproduce).
  frame::OffscreenFrame render_exact_optical_depth(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h) {
    frame::FrameRenderer renderer(device(), mesh);
    frame::FrameSettings settings = settings_on_backend();
    settings.resolve.quantity = volume::Quantity::OpticalDepth;
    return renderer.render_offscreen(camera, settings, {w, h});
  }
};

}  // namespace prismoid::test
