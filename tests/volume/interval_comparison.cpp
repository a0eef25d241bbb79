// Tolerance, per pixel, from the math of the two error sources:
//  1. The rasterizer snaps proxy vertices to a grid of 2^-b pixel (b = subPixelPrecisionBits,
//     each vertex moves by at most 2^-(b+1) per axis) and interpolates the attributes with
//     the barycentrics l'_i of the pixel centre x in the snapped triangle p'_i. Since the
//     attributes (1/depth of the two bounding faces) are affine over the original triangle
//     p_i, the result is the exact value at y = sum l'_i p_i, and y - x = sum l'_i (p_i - p'_i)
//     is a convex combination of the vertex displacements: |y - x| <= 2^-(b+1) per axis,
//     for every proxy shape (no barycentric amplification, slivers included). The point y
//     differs from cell to cell (each proxy has its own triangles), so neighbouring cells'
//     changes need not cancel: a face that is nearly edge-on has a steep depth, and the two
//     cells sharing it can both gain (seen on a 215k-cell mesh: +0.0033 each at one pixel).
//     Hence the tolerance is the sum over cells of each cell's largest change within 2 * 2^-b
//     of the pixel centre (reference::snapping_variation_image; the factor 4 over 2^-(b+1) is
//     margin for sampling 8 points only), with the one-sided limits at cell vertices within
//     reach, where the depth of a cell with a face through the eye jumps.
//  2. float32 arithmetic: depths come back from interpolated 1/depth after projection,
//     barycentric interpolation and a reciprocal, a budget of 32 ulp = 2^-19 relative per
//     surface, hence sigma * 2 * depth_max * 2^-19 * (ray length per unit depth, largest at
//     the image corners: sqrt(1 + tan^2(fovy/2) (1 + aspect^2))) for each segment drawn
//     along the ray, plus the rounding of the additive blend, one ulp of the sum per segment.
//     A cell is one segment, except that a cell cut by the near plane is drawn as up to three
//     pieces, each with its own surfaces and rounding: it counts three.
//     Not covered: the inner proxy vertex's computed attributes (case 1 barycentrics, case 2
//     crossing) round with an error amplified by the proxy's longest edge over its smallest
//     height; the sliver tests pass within the budget, but it is not a derived bound.
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
  std::vector<uint32_t> clipped_hits(ref.size(), 0u);  // rays through cells the near plane cuts
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  auto cut_by_near_plane = [&](size_t c) {
    bool before = false, beyond = false;
    for (uint32_t v : mesh.tets[c]) (glm::dot(mesh.points[v] - camera.eye, forward) < camera.near_distance ? before : beyond) = true;
    return before && beyond;
  };
  reference::trace_cells(mesh, camera, w, h, 0.0, 0.0, cut_by_near_plane,
                         [&](size_t pixel, size_t, const reference::Interval&, const glm::dvec3&) { ++clipped_hits[pixel]; });
  // Sampling radius 2 * 2^-b: four times the largest displacement 2^-(b+1), a margin for
  // sampling the extremes of a cell's optical depth at 8 points only.
  const double radius = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
  const std::vector<double> snap_tol = reference::snapping_variation_image(mesh, camera, w, h, radius);
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
    const double segments = cells_hit[i] + 2.0 * clipped_hits[i];
    const double float_tol = (segments + 1.0) * (per_cell_tol + ref[i] * std::ldexp(1.0, -24));
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
