// Tolerance, per pixel, from the math of the two error sources:
//  1. The rasterizer snaps proxy vertices to a grid of 2^-b pixel (b = subPixelPrecisionBits,
//     each vertex moves by at most 2^-(b+1) per axis) and interpolates the attributes there.
//     Inside a proxy triangle the interpolated value is then the exact value at a point moved
//     by the vertices' displacement times the triangle's barycentric amplification, which we
//     bound by 4 for the proxies met here (amplification near 1 for well-shaped triangles;
//     thin proxies at the view's edge when the camera is inside the mesh need more than 2).
//     So the tolerance is the largest difference between the reference at the centre and
//     at the 8 points at distance 2 * 2^-b around it; this also covers pixels whose
//     coverage flips at a silhouette edge. Slivers get their own bound with issue 3.
//  2. float32 arithmetic: depths come back from interpolated 1/depth after projection,
//     barycentric interpolation and a reciprocal, a budget of 32 ulp = 2^-19 relative per
//     surface, hence sigma * 2 * depth_max * 2^-19 * (ray length per unit depth, largest at
//     the image corners: sqrt(1 + tan^2(fovy/2) (1 + aspect^2))) for each cell the ray
//     crosses, plus the rounding of the additive blend, one ulp of the sum per cell added.
#include "volume/interval_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/tet_ray.hpp"

namespace prismoid::test {

std::vector<float> IntervalShadingTest::render(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h) {
  frame::FrameRenderer renderer(device(), mesh);
  frame::FrameSettings settings;
  settings.resolve.quantity = volume::Quantity::OpticalDepth;
  return renderer.render_offscreen(camera, settings, {w, h}).quantity;
}

IntervalShadingTest::Comparison IntervalShadingTest::compare(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h) {
  const std::vector<float> gpu = render(mesh, camera, w, h);
  std::vector<uint32_t> cells_hit;
  const std::vector<double> ref = reference::optical_depth_image(mesh, camera, w, h, 0.0, 0.0, &cells_hit);
  const double s = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
  std::vector<double> snap_tol(ref.size(), 0.0);
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (!dx && !dy) continue;
      const auto shifted = reference::optical_depth_image(mesh, camera, w, h, dx * s, dy * s);
      for (size_t i = 0; i < ref.size(); ++i) snap_tol[i] = std::max(snap_tol[i], std::abs(shifted[i] - ref[i]));
    }
  double depth_max = 0.0, sigma_max = 0.0;
  for (const auto& p : mesh.points) depth_max = std::max(depth_max, glm::length(p - camera.eye));
  for (double sg : mesh.cell_extinction) sigma_max = std::max(sigma_max, sg);
  for (double sg : mesh.point_extinction) sigma_max = std::max(sigma_max, sg);
  const double tan_half = std::tan(glm::radians(camera.fovy_degrees) * 0.5), aspect = double(w) / double(h);
  const double length_per_depth = std::sqrt(1.0 + tan_half * tan_half * (1.0 + aspect * aspect));
  const double per_cell_tol = sigma_max * 2.0 * depth_max * std::ldexp(1.0, -19) * length_per_depth;

  Comparison c;
  size_t non_finite = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (!std::isfinite(gpu[i]) && non_finite++ < 8)
      ADD_FAILURE() << "pixel (" << i % w << "," << i / w << ") is not finite: " << gpu[i];
    const double err = std::abs(double(gpu[i]) - ref[i]);
    if (ref[i] > 0.0) ++c.covered;
    c.max_error = std::max(c.max_error, err);
    const double float_tol = (cells_hit[i] + 1) * (per_cell_tol + ref[i] * std::ldexp(1.0, -24));
    if (!(err <= snap_tol[i] + float_tol)) {
      if (c.failures++ == 0)
        c.first_failure = "pixel (" + std::to_string(i % w) + "," + std::to_string(i / w) + "): gpu " + std::to_string(gpu[i]) +
                          " reference " + std::to_string(ref[i]) + " tolerance " + std::to_string(snap_tol[i] + float_tol);
      if (c.failed_pixels.size() < 64) c.failed_pixels.push_back(i);
    }
    if (ref[i] > 0.0) c.max_relative_to_tolerance = std::max(c.max_relative_to_tolerance, err / (snap_tol[i] + float_tol));
  }
  EXPECT_EQ(non_finite, 0u) << "non-finite pixels in a " << w << "x" << h << " image";
  return c;
}

}  // namespace prismoid::test
