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
//  2. The positions the GPU receives: float, relative to the mesh's bounds centre (a rounding of
//     up to 2^-24 of each point's distance from it). The reference is traced on those exact
//     float positions too (the snapping term above is measured on them), and the difference of
//     the two references is added: it is what the rounded input changes, computed, not guessed.
//  3. float32 arithmetic in the shaders (tet_projection.glsl, interval_ray.glsl): each surface's
//     depth is recovered relative to the cell's reference point c (its first vertex) as
//     ((depth - depth_c)/depth) * depth, from vertex values of at most Dz/d_min in size (Dz: the
//     cell's depth extent, d_min..d_max: its depths beyond the near plane), interpolated and
//     multiplied back by a depth up to d_max; a budget of 32 ulp = 2^-19 of Dz d_max / d_min per
//     surface, hence sigma_max * 2 * 2^-19 * Dz * (d_max / d_min) * (ray length per unit depth)
//     per segment, and the same for the field's values at the ends (2^-19 of the cell's sigma
//     range times d_max / d_min, times the segment's length). A segment of a cell cut by the near
//     plane also moves with the plane, placed relative to c from (near - depth of the mesh
//     centre) and c's offset from that centre: 2^-19 of their sizes per end. Such a cell is drawn
//     as up to three pieces, each with its own surfaces and rounding: it counts three. Plus the
//     rounding of the additive blend, one ulp of the sum per segment. A cell the reference's ray
//     misses can still be drawn at the pixel (zero volume, or its snapped proxy covers it): one
//     more segment, with the largest budget of the mesh's cells.
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
#include "scene/tet_mesh.hpp"

namespace prismoid::test {

std::vector<float> IntervalShadingTest::render(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h) {
  frame::FrameRenderer renderer(device(), mesh);
  frame::FrameSettings settings = settings_on_backend();
  settings.resolve.quantity = volume::Quantity::OpticalDepth;
  return renderer.render_offscreen(camera, settings, {w, h}).quantity;
}

namespace {

// The mesh as the GPU receives it: positions rounded to float relative to the bounds centre.
TetMesh as_uploaded(const TetMesh& mesh) {
  TetMesh m = mesh;
  const glm::dvec3 origin = bounds_of(mesh).center();
  for (auto& p : m.points) p = glm::dvec3(glm::vec3(p - origin)) + origin;
  return m;
}

}  // namespace

IntervalShadingTest::Comparison IntervalShadingTest::compare(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h) {
  return compare_image(render(mesh, camera, w, h), mesh, camera, w, h);
}

IntervalShadingTest::Comparison IntervalShadingTest::compare_image(const std::vector<float>& gpu, const TetMesh& mesh,
                                                                   const Camera& camera, uint32_t w, uint32_t h,
                                                                   const std::vector<double>& extra) {
  const TetMesh uploaded = as_uploaded(mesh);
  const std::vector<double> ref = reference::optical_depth_image(mesh, camera, w, h);
  std::vector<uint32_t> cells_hit;
  const std::vector<double> ref_uploaded = reference::optical_depth_image(uploaded, camera, w, h, 0.0, 0.0, &cells_hit);
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 origin = bounds_of(mesh).center();
  double mesh_radius = 0.0;  // largest distance of a point from the origin the positions are relative to
  for (const auto& p : uploaded.points) mesh_radius = std::max(mesh_radius, glm::length(p - origin));
  const double near_from_origin = std::abs(camera.near_distance - glm::dot(origin - camera.eye, forward));
  const double budget = std::ldexp(1.0, -19);
  // Term 3 for one segment of cell c along a ray with `length_per_depth`, `length` long.
  auto segment_tolerance = [&](size_t c, double length_per_depth, double length, bool& clipped) {
    double d_lo = 1e300, d_hi = -1e300, s_lo = uploaded.cell_extinction[c], s_hi = s_lo;
    for (uint32_t v : uploaded.tets[c]) {
      const double d = glm::dot(uploaded.points[v] - camera.eye, forward);
      d_lo = std::min(d_lo, d);
      d_hi = std::max(d_hi, d);
      if (uploaded.linear_extinction()) {
        s_lo = std::min(s_lo, uploaded.point_extinction[v]);
        s_hi = std::max(s_hi, uploaded.point_extinction[v]);
      }
    }
    clipped = d_lo < camera.near_distance;
    if (d_hi < camera.near_distance) return 0.0;  // wholly behind the near plane: never drawn
    const double ratio = d_hi / std::max(d_lo, camera.near_distance);
    const double tol = budget * ratio * (s_hi * 2.0 * (d_hi - d_lo) * length_per_depth + (s_hi - s_lo) * length);
    return clipped ? 3.0 * (tol + budget * s_hi * 2.0 * (near_from_origin + mesh_radius) * length_per_depth) : tol;
  };
  std::vector<double> float_tol(ref.size(), 0.0);
  std::vector<uint32_t> clipped_hits(ref.size(), 0u);
  reference::trace_cells(uploaded, camera, w, h, 0.0, 0.0, [](size_t) { return true; },
                         [&](size_t pixel, size_t c, const reference::Interval& in, const glm::dvec3& dir) {
    bool clipped = false;
    float_tol[pixel] += segment_tolerance(c, 1.0 / glm::dot(dir, forward), in.length(), clipped);
    if (clipped) ++clipped_hits[pixel];
  });
  // A cell the reference's ray just misses (a zero-volume cell, or one whose snapped proxy
  // covers the pixel) is still drawn there with its own rounding: one more segment's budget,
  // the largest of the mesh's (at the image corners' ray length per unit depth, and the
  // longest segment a cell can hold, its longest edge).
  const double tan_half = std::tan(glm::radians(camera.fovy_degrees) * 0.5), aspect = double(w) / double(h);
  const double corner_length_per_depth = std::sqrt(1.0 + tan_half * tan_half * (1.0 + aspect * aspect));
  double extra_segment = 0.0;
  for (size_t cell = 0; cell < uploaded.tets.size(); ++cell) {
    double longest = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        longest = std::max(longest, glm::distance(uploaded.points[uploaded.tets[cell][i]], uploaded.points[uploaded.tets[cell][j]]));
    bool clipped = false;
    extra_segment = std::max(extra_segment, segment_tolerance(cell, corner_length_per_depth, longest, clipped));
  }
  // Sampling radius 2 * 2^-b: four times the largest displacement 2^-(b+1), a margin for
  // sampling the extremes of a cell's optical depth at 8 points only.
  const double radius = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
  const std::vector<double> snap_tol = reference::snapping_variation_image(uploaded, camera, w, h, radius);
  const std::vector<double> sensitivity = reference::surface_sensitivity_image(uploaded, camera, w, h, radius);

  Comparison c;
  size_t non_finite = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (!std::isfinite(gpu[i]) && non_finite++ < 8)
      ADD_FAILURE() << "pixel (" << i % w << "," << i / w << ") is not finite: " << gpu[i];
    const double err = std::abs(double(gpu[i]) - ref[i]);
    if (ref[i] > 0.0) ++c.covered;
    c.max_error = std::max(c.max_error, err);
    const double segments = cells_hit[i] + 2.0 * clipped_hits[i];
    // Term 4: attribute interpolation in window coordinates, 2^-19 of (x + y + 1) pixels.
    const double interpolation = budget * double(i % w + i / w + 1) * sensitivity[i];
    const double tolerance = snap_tol[i] + float_tol[i] + extra_segment + interpolation +
                             (segments + 1.0) * ref_uploaded[i] * std::ldexp(1.0, -24) +
                             std::abs(ref[i] - ref_uploaded[i]) + (extra.empty() ? 0.0 : extra[i]);
    if (!(err <= tolerance)) {
      if (c.failures++ == 0)
        c.first_failure = "pixel (" + std::to_string(i % w) + "," + std::to_string(i / w) + "): gpu " + std::to_string(gpu[i]) +
                          " reference " + std::to_string(ref[i]) + " tolerance " + std::to_string(tolerance);
      if (c.failed_pixels.size() < 64) c.failed_pixels.push_back(i);
    }
    if (ref[i] > 0.0) c.max_relative_to_tolerance = std::max(c.max_relative_to_tolerance, err / tolerance);
  }
  EXPECT_EQ(non_finite, 0u) << "non-finite pixels in a " << w << "x" << h << " image";
  return c;
}

}  // namespace prismoid::test
