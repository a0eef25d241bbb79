// Marching a sampled grid inside intervals (FieldKind::Grid): the shader's float trilinear
// interpolation from a storage buffer against the double reference. Each test states where its
// tolerance comes from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <memory>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/analytic_march.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "renderer/volume/region_mesh.hpp"
#include "scene/tet_mesh.hpp"
#include "support/backends.hpp"
#include "support/gpu_fixture.hpp"
#include "support/march_fixture.hpp"

namespace prismoid {
namespace {

using test::kUlp;
using test::looking_from;
using GridMarchTest = test::MarchTest;

void expect_finite(const std::vector<float>& image, const char* what) {
  size_t bad = 0;
  for (float v : image) bad += std::isfinite(v) ? 0 : 1;
  EXPECT_EQ(bad, 0u) << what;
}

// Blocks of 8^3 samples from sample `margin` on (a lattice not at 0), kept where one of the
// samples the block's field depends on is above `threshold`. The regions stay `margin`
// samples inside the grid: snapping moves a fragment's interval ends off its cell, and where
// that reaches past the grid's box the grid gives its background, which no test below models.
std::vector<volume::IndexBox> inner_blocks_above(const volume::SampledGrid& g, double threshold, int margin) {
  std::vector<volume::IndexBox> boxes;
  const glm::ivec3 end = glm::ivec3(g.dims) - 1 - margin;
  for (int k = margin; k + 8 <= end.z; k += 8)
    for (int j = margin; j + 8 <= end.y; j += 8)
      for (int i = margin; i + 8 <= end.x; i += 8) {
        bool above = false;
        for (int z = k; z <= k + 8; ++z)
          for (int y = j; y <= j + 8; ++y)
            for (int x = i; x <= i + 8; ++x) above = above || double(g.values[g.index(uint32_t(x), uint32_t(y), uint32_t(z))]) > threshold;
        if (above) boxes.push_back({{i, j, k}, glm::ivec3(8)});
      }
  return boxes;
}

// (a) A grid sampled from a linear function with dyadic coefficients on a dyadic lattice holds
// the function exactly (every sample is exact in float), and trilinear interpolation
// reproduces linear functions, so the marched grid is the linear field: the midpoint rule is
// exact for it, and the march must give what exact interval shading gives for the region
// mesh's point extinction (the same linear field, exactly: its points are samples), through the
// same proxies (snapping cancels). The regions are the blocks above a threshold (not convex);
// one camera is inside them. What remains is float, as for the analytic linear field
// (test_interval_march.cpp): n samples summed plus interval shading's mean * length,
// tau (n + 16) 2^-23; sample positions off by 8 roundings of max(|eye|, distance), times |g|
// over the ray's length L; and the trilinear interpolation's own rounding, 3 levels of
// a + t (b - a), each at most 3 roundings of the largest value (plus the fraction t's
// rounding, a position error inside the first term): 16 ulp of max|v| per sample, times L.
TEST_P(GridMarchTest, LinearGridMarchEqualsExactIntervalShading) {
  const glm::dvec3 g(0.25, -0.125, 0.25);
  const volume::AnalyticField linear = volume::linear_field(g, 1.0);
  auto grid = std::make_shared<volume::SampledGrid>(volume::sample_onto_grid(linear, glm::uvec3(41), glm::dvec3(-1.25), glm::dvec3(1.25)));
  const auto regions = inner_blocks_above(*grid, 1.2, 4);  // in [-1, 1]^3
  const TetMesh mesh = volume::make_region_mesh(*grid, regions);
  ASSERT_LT(regions.size(), 64u);
  ASSERT_GT(regions.size(), 16u);
  const volume::AnalyticField field = volume::grid_field(grid);
  const double v_max = volume::max_abs_value(*grid), diagonal = 2.0 * std::sqrt(3.0);
  for (const Camera& camera : {looking_from({0.4, 0.3, 4.5}), looking_from({-3.0, 2.0, -2.5}),
                               looking_from({0.2, 0.1, 0.3}, {0.5, -0.3, -1.0}, 80.0)}) {
    const double step = 0.05;
    const auto march = render(mesh, field, volume::Quantity::OpticalDepth, step, camera, 40, 40);
    const auto exact = render_exact_optical_depth(mesh, camera, 40, 40);
    expect_finite(march.quantity, "march");
    const double longest = std::sqrt(3.0) * 0.5;  // a block's diagonal: 8 samples of 1/16
    const double n = std::ceil(longest / step);
    const double reach = glm::length(camera.eye) + diagonal;
    size_t covered = 0;
    double worst = 0.0;
    for (size_t i = 0; i < exact.quantity.size(); ++i) {
      const double tau = exact.quantity[i];
      if (tau > 0.0) ++covered;
      const double tol = tau * (n + 16.0) * 2.0 * kUlp + (glm::length(g) * 8.0 * reach + 16.0 * v_max) * kUlp * diagonal +
                         snapped_field_tolerance(camera, 40, glm::length(g), reach, diagonal);
      const double err = std::abs(double(march.quantity[i]) - tau);
      worst = std::max(worst, err / tol);
      EXPECT_LE(err, tol) << "pixel " << i << ": march " << march.quantity[i] << " exact " << tau;
    }
    EXPECT_GT(covered, 200u);
    std::printf("linear grid: worst pixel at %.3f of its tolerance\n", worst);
  }
}

// Per pixel and cell: the cell's interval at the pixel centre (distances along the pixel ray),
// and how far its ends can move on the GPU: the fragment's samples lie on the exact pixel ray,
// but its front and back depths are those of the cell's faces at a point within `radius`
// pixels (snapped proxy vertices, see tests/volume/interval_comparison.cpp), sampled at 8
// neighbours (the factor 4 in the radius is the margin for sampling), converted to distance
// along the centre ray. A cell seen only by a neighbour has an empty interval at the centre.
struct CellEnds {
  double enter = 0.0, exit = 0.0;          // at the pixel centre
  double move_enter = 0.0, move_exit = 0.0;  // largest movement of each end
};

std::vector<std::map<size_t, CellEnds>> cell_ends(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h, double radius) {
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  auto depths = [&](double ox, double oy) {
    std::vector<std::map<size_t, reference::Interval>> cells(size_t(w) * h);
    reference::trace_cells(mesh, camera, w, h, ox, oy, [](size_t) { return true; },
                           [&](size_t pixel, size_t cell, const reference::Interval& in, const glm::dvec3& dir) {
                             const double to_depth = glm::dot(dir, forward);
                             cells[pixel][cell] = {in.enter * to_depth, in.exit * to_depth};
                           });
    return cells;
  };
  const auto centre = depths(0.0, 0.0);
  std::vector<std::map<size_t, CellEnds>> ends(centre.size());
  for (size_t p = 0; p < centre.size(); ++p)
    for (const auto& [c, in] : centre[p]) ends[p][c] = {in.enter, in.exit, 0.0, 0.0};
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      if (!dx && !dy) continue;
      const auto moved = depths(dx * radius, dy * radius);
      for (size_t p = 0; p < centre.size(); ++p) {
        for (const auto& [c, in] : moved[p])
          if (!ends[p].count(c)) ends[p][c] = {in.enter, in.enter, 0.0, 0.0};  // depths for now
        for (auto& [c, e] : ends[p]) {
          const auto it = moved[p].find(c);
          const reference::Interval m = it != moved[p].end() ? it->second : reference::Interval{e.enter, e.enter};
          e.move_enter = std::max(e.move_enter, std::abs(m.enter - e.enter));
          e.move_exit = std::max(e.move_exit, std::abs(m.exit - e.exit));
        }
      }
    }
  for (size_t p = 0; p < ends.size(); ++p) {
    const glm::dvec3 dir = reference::ray_direction(camera, w, h, double(p % w) + 0.5, double(p / w) + 0.5);
    const double length_per_depth = 1.0 / glm::dot(dir, forward);
    for (auto& [c, e] : ends[p]) {
      e.enter *= length_per_depth;
      e.exit *= length_per_depth;
      e.move_enter *= length_per_depth;
      e.move_exit *= length_per_depth;
    }
  }
  return ends;
}

// (b) A grid of Marschner-Lobb (samples 1/16 apart; regions in [-1, 1]^3): its trilinear field has kinks at
// every voxel face, so no step bound holds; instead the GPU march is compared with the same
// march in double (reference::field_march_optical_depth_image: the same ceil(L / S) midpoint
// samples per cell). sigma = max(f, 0) is G-Lipschitz along any line, G = gradient_bound, and
// at most s = max|v|. Per cell of length L whose ends move by da, db (snapping, above, plus
// float depths: 2^-19 of the depth per end, interval_comparison.cpp):
//  - with the same step count n, h moves by (da + db) / n and every sample by at most
//    max(da, db), so the sum moves by (da + db) s + (L + da + db) G max(da, db);
//  - if ceil((L -+ (da + db)) / S) differ, the GPU may take another n: each midpoint sum is
//    within G h^2 / 4 per step of the integral (a Lipschitz integrand), so the two differ by
//    (da + db) s + G (L + da + db) S / 2;
// plus float over the ray (length <= the box's diagonal D): positions 8 roundings of
// max(|eye|, distance) times G, 16 ulp of s per sample for the interpolation, and the sums,
// tau (n + 16) 2^-23.
TEST_P(GridMarchTest, MarschnerLobbGridMatchesTheDoubleMarchAtTheSameStep) {
  auto grid = std::make_shared<volume::SampledGrid>(
      volume::sample_onto_grid(volume::marschner_lobb(), glm::uvec3(41), glm::dvec3(-1.25), glm::dvec3(1.25)));
  const TetMesh mesh = volume::make_region_mesh(*grid, inner_blocks_above(*grid, 0.45, 4));
  const volume::AnalyticField field = volume::grid_field(grid);
  const double s = volume::max_abs_value(*grid), G = volume::gradient_bound(*grid), diagonal = 2.0 * std::sqrt(3.0);
  const uint32_t w = 48, h = 48;
  const double step = 0.02;
  const double radius = 2.0 * std::ldexp(1.0, -int(device().capabilities().subpixel_precision_bits));
  for (const Camera& camera : {looking_from({0.9, 0.7, 3.6}), looking_from({-2.9, -1.2, 1.7})}) {
    const auto gpu = render(mesh, field, volume::Quantity::OpticalDepth, step, camera, w, h).quantity;
    expect_finite(gpu, "march");
    const std::vector<double> cpu = reference::field_march_optical_depth_image(mesh, field, 1.0, camera, w, h, step);
    const auto ends = cell_ends(mesh, camera, w, h, radius);
    const double reach = glm::length(camera.eye) + diagonal;
    double worst = 0.0, max_err = 0.0;
    std::vector<double> tolerances;
    size_t covered = 0;
    for (size_t p = 0; p < cpu.size(); ++p) {
      double tol = 0.0;
      for (const auto& [c, e] : ends[p]) {
        const double L = e.exit - e.enter, float_depth = std::ldexp(1.0, -19) * e.exit;
        const double da = e.move_enter + float_depth, db = e.move_exit + float_depth;
        const bool same_n = std::ceil(std::max(L - da - db, 0.0) / step) == std::ceil((L + da + db) / step);
        tol += (da + db) * s + (same_n ? (L + da + db) * G * std::max(da, db) : G * (L + da + db) * step / 2.0);
      }
      tol += cpu[p] * (std::ceil(0.5 * std::sqrt(3.0) / step) + 16.0) * 2.0 * kUlp + (G * 8.0 * reach + 16.0 * s) * kUlp * diagonal;
      const double err = std::abs(double(gpu[p]) - cpu[p]);
      max_err = std::max(max_err, err);
      if (cpu[p] > 0.0) {
        ++covered;
        tolerances.push_back(tol);
        worst = std::max(worst, err / tol);
      }
      EXPECT_LE(err, tol) << "pixel (" << p % w << "," << p / w << "): gpu " << gpu[p] << " cpu " << cpu[p];
    }
    ASSERT_GT(covered, 400u);
    std::sort(tolerances.begin(), tolerances.end());
    std::printf("Marschner-Lobb grid: max error %.3g, median tolerance %.3g (optical depths up to %.3g), worst pixel at %.3f of its tolerance\n",
                max_err, tolerances[tolerances.size() / 2], *std::max_element(cpu.begin(), cpu.end()), worst);
  }
}

// (c) A grid of 1 - |p - c| (a sphere's distance function, 1-Lipschitz): trilinear
// interpolation is a convex combination of the voxel's 8 samples, each within sqrt(3) voxel
// sizes (the voxel's diagonal d) of the point, so it is within d of 1 - |p - c| everywhere.
// Hence the isosurface at 1 - r lies within d of the sphere of radius r: a hit's distance to c
// is within d of r (plus float: positions 2^-20 of max(|eye|, distance), the bisection one
// float of depth); rays passing farther than r + d from c never hit; rays passing within
// r - d - step of it hit (the chord where the field is above the isovalue is longer than a
// step, so the march cannot step over it). Also a camera inside the sphere: every pixel hits
// (the interval starts above the isovalue) and nothing is NaN.
TEST_P(GridMarchTest, SphereDistanceGridIsosurfaceLiesWithinOneVoxel) {
  auto grid = std::make_shared<volume::SampledGrid>();
  grid->name = "sphere distance";
  grid->dims = glm::uvec3(33);
  grid->origin = glm::dvec3(-1.0);
  grid->spacing = glm::dvec3(1.0 / 16.0);
  const glm::dvec3 centre(0.1, -0.05, 0.05);
  const double r = 0.5, iso = 1.0 - r, d = std::sqrt(3.0) / 16.0;
  for (uint32_t k = 0; k < 33; ++k)
    for (uint32_t j = 0; j < 33; ++j)
      for (uint32_t i = 0; i < 33; ++i) grid->values.push_back(float(1.0 - glm::length(grid->position(glm::dvec3(i, j, k)) - centre)));
  const TetMesh mesh = volume::make_region_mesh(*grid, volume::whole_grid(*grid));
  const volume::AnalyticField field = volume::grid_field(grid);
  const double step = 0.02;
  const uint32_t w = 48, h = 48;
  for (const glm::dvec3 eye : {glm::dvec3(0.3, 0.2, 2.4), glm::dvec3(-1.7, 1.1, -1.4)}) {
    const Camera camera = looking_from(eye);
    const auto gpu = render(mesh, field, volume::Quantity::Isosurface, step, camera, w, h, iso);
    expect_finite(gpu.emission, "isosurface");
    size_t hits = 0, misses = 0;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        const glm::dvec3 dir = reference::ray_direction(camera, w, h, x + 0.5, y + 0.5);
        const double along = glm::dot(centre - eye, dir);
        const double b = std::sqrt(std::max(glm::dot(centre - eye, centre - eye) - along * along, 0.0));
        const double distance = gpu.emission[4 * i + 3];
        const double slack = std::ldexp(1.0, -20) * (glm::length(eye) + 4.0);
        if (b > r + d + slack) {
          EXPECT_EQ(distance, 0.0) << "pixel (" << x << "," << y << ") passes " << b - r << " outside the sphere";
          ++misses;
        } else if (b < r - d - step) {
          EXPECT_GT(distance, 0.0) << "pixel (" << x << "," << y << ") passes " << r - b << " inside the sphere";
        }
        if (distance > 0.0) {
          ++hits;
          EXPECT_NEAR(glm::length(eye + distance * dir - centre), r, d + 2.0 * slack) << "pixel (" << x << "," << y << ")";
        }
      }
    EXPECT_GT(hits, 100u);
    EXPECT_GT(misses, 100u);
  }
  const Camera inside = looking_from(centre + glm::dvec3(0.05, 0.1, 0.0), glm::dvec3(0.5, 0.5, -1.0), 70.0);
  const auto gpu = render(mesh, field, volume::Quantity::Isosurface, step, inside, w, h, iso);
  expect_finite(gpu.emission, "isosurface from inside");
  for (size_t i = 0; i < size_t(w) * h; ++i) EXPECT_GT(gpu.emission[4 * i + 3], 0.0f) << "pixel " << i;
  const auto depth = render(mesh, field, volume::Quantity::OpticalDepth, step, inside, w, h);
  expect_finite(depth.quantity, "optical depth from inside");
  for (float v : depth.quantity) EXPECT_GT(v, 0.0f);
}

PRISMOID_ON_BOTH_BACKENDS(GridMarchTest);

}  // namespace
}  // namespace prismoid
