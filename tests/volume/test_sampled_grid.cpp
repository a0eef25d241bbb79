// Sampled grids (renderer/volume/sampled_grid.*) and the region meshes that bound them for
// marching (renderer/volume/region_mesh.*), on the CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/volume/analytic_field.hpp"
#include "renderer/volume/region_mesh.hpp"
#include "renderer/volume/sampled_grid.hpp"
#include "scene/input_error.hpp"
#include "support/mesh_faces.hpp"

namespace prismoid {
namespace {

volume::SampledGrid random_grid(glm::uvec3 dims, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(-2.0f, 3.0f);
  volume::SampledGrid g;
  g.dims = dims;
  g.origin = {0.3, -1.2, 2.5};
  g.spacing = {0.5, 0.25, 0.75};
  g.background = -7.0;
  for (size_t i = 0; i < size_t(dims.x) * dims.y * dims.z; ++i) g.values.push_back(value(rng));
  return g;
}

// Trilinear interpolation written as the sum over all samples of value times the tensor
// product of hat functions max(0, 1 - |u - i|): independent of how evaluate() finds the voxel.
double hat_sum(const volume::SampledGrid& g, const glm::dvec3& p) {
  const glm::dvec3 u = (p - g.origin) / g.spacing;
  double sum = 0.0;
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t j = 0; j < g.dims.y; ++j)
      for (uint32_t i = 0; i < g.dims.x; ++i) {
        const double w = std::max(0.0, 1.0 - std::abs(u.x - i)) * std::max(0.0, 1.0 - std::abs(u.y - j)) *
                         std::max(0.0, 1.0 - std::abs(u.z - k));
        sum += w * double(g.values[g.index(i, j, k)]);
      }
  return sum;
}

// Tolerances: a few roundings (2^-53 relative) of values of size <= 3 and index coordinates
// of size <= 8: 1e-13 is far above, and far below any real disagreement.
TEST(SampledGrid, EvaluationEqualsTheTrilinearClosedForm) {
  const volume::SampledGrid g = random_grid({5, 4, 6}, 7);
  ASSERT_NO_THROW(volume::validate(g));
  const Bounds b = volume::bounds_of(g);
  EXPECT_EQ(b.max, g.origin + glm::dvec3(4, 3, 5) * g.spacing);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> t(0.0, 1.0);
  for (int n = 0; n < 2000; ++n) {
    const glm::dvec3 p = b.min + glm::dvec3(t(rng), t(rng), t(rng)) * (b.max - b.min);
    EXPECT_NEAR(volume::evaluate(g, p), hat_sum(g, p), 1e-13);
  }
  // At the samples (faces and corners of the box included) it is the sample.
  for (uint32_t k = 0; k < g.dims.z; ++k)
    for (uint32_t j = 0; j < g.dims.y; ++j)
      for (uint32_t i = 0; i < g.dims.x; ++i)
        EXPECT_NEAR(volume::evaluate(g, g.position(glm::dvec3(i, j, k))), g.values[g.index(i, j, k)], 1e-13);
  // Outside, the background, however near.
  EXPECT_EQ(volume::evaluate(g, b.max + glm::dvec3(1e-9, 0.0, 0.0)), g.background);
  EXPECT_EQ(volume::evaluate(g, b.min - glm::dvec3(0.0, 0.0, 1e-9)), g.background);
  EXPECT_EQ(volume::gradient(g, b.min - glm::dvec3(1.0)), glm::dvec3(0.0));
}

// Inside a voxel the interpolant is smooth: central differences of step 1e-5 agree with the
// gradient to O(e^2 |f'''|) + rounding 1e-13 / e = 1e-8; with the voxel's second
// derivatives (<= |values| range / spacing^2 ~ 100) the e^2 term is 1e-8 too.
TEST(SampledGrid, GradientIsTheDerivativeInsideVoxels) {
  const volume::SampledGrid g = random_grid({4, 5, 3}, 11);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> cell(0.05, 0.95);
  std::uniform_int_distribution<uint32_t> pick(0, 1);
  const double e = 1e-5;
  for (int n = 0; n < 500; ++n) {
    const glm::dvec3 ijk(pick(rng) + cell(rng), pick(rng) + cell(rng), pick(rng) + cell(rng));
    const glm::dvec3 p = g.position(ijk);
    const glm::dvec3 grad = volume::gradient(g, p);
    for (int a = 0; a < 3; ++a) {
      glm::dvec3 d(0.0);
      d[a] = e;
      EXPECT_NEAR(grad[a], (volume::evaluate(g, p + d) - volume::evaluate(g, p - d)) / (2.0 * e), 1e-6);
    }
    EXPECT_LE(glm::length(grad), volume::gradient_bound(g));
  }
}

// Trilinear interpolation is exact for linear functions. With dyadic coefficients, origin and
// spacing, every sample is exact in float, so the grid is the linear function up to double
// rounding of the evaluation (values <= 4, 1e-14).
TEST(SampledGrid, LinearFunctionIsReproducedExactly) {
  const volume::AnalyticField linear = volume::linear_field({0.25, -0.5, 0.125}, 1.0);
  const volume::SampledGrid g = volume::sample_onto_grid(linear, {9, 5, 17}, glm::dvec3(-1.0), glm::dvec3(1.0));
  EXPECT_EQ(g.spacing, glm::dvec3(0.25, 0.5, 0.125));
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> c(-1.0, 1.0);
  for (int n = 0; n < 2000; ++n) {
    const glm::dvec3 p(c(rng), c(rng), c(rng));
    EXPECT_NEAR(volume::evaluate(g, p), volume::evaluate(linear, p), 1e-14);
    const glm::dvec3 grad = volume::gradient(g, p);
    EXPECT_NEAR(glm::length(grad - glm::dvec3(0.25, -0.5, 0.125)), 0.0, 1e-13);
  }
  // As a field: the same through the AnalyticField interface, and moved exactly.
  const volume::AnalyticField field = volume::grid_field(std::make_shared<volume::SampledGrid>(g));
  const auto moved = volume::translated(field, {3.0, -2.0, 0.5});
  ASSERT_TRUE(moved.has_value());
  EXPECT_TRUE(std::isinf(volume::second_derivative_bound(field)));
  EXPECT_NEAR(volume::evaluate(*moved, glm::dvec3(0.1, 0.2, 0.3) - glm::dvec3(3.0, -2.0, 0.5)),
              volume::evaluate(field, glm::dvec3(0.1, 0.2, 0.3)), 1e-14);
}

TEST(SampledGrid, InvalidGridsNameTheProblem) {
  auto message = [](const volume::SampledGrid& g) {
    try {
      volume::validate(g);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  volume::SampledGrid g = random_grid({2, 2, 2}, 1);
  g.name = "density";
  EXPECT_EQ(message(g), "no error");
  auto bad = g;
  bad.values[3] = std::nanf("");
  EXPECT_EQ(message(bad), "density: has a non-finite value");
  bad = g;
  bad.spacing.y = 0.0;
  EXPECT_EQ(message(bad), "density: the spacing must be positive and finite");
  bad = g;
  bad.dims.z = 0;
  EXPECT_EQ(message(bad), "density: a grid needs at least one sample per axis");
  bad = g;
  bad.values.pop_back();
  EXPECT_EQ(message(bad), "density: has 7 values for 8 samples");
  EXPECT_THROW(volume::validate(volume::grid_field(nullptr)), InputError);
}

// The union of the boxes' regions as voxels (voxel v spans samples v .. v + 1): a box of
// `size` samples from `min` covers voxels min .. min + size - 1, clipped to the grid.
std::set<std::tuple<int, int, int>> union_voxels(const volume::SampledGrid& g, const std::vector<volume::IndexBox>& boxes) {
  std::set<std::tuple<int, int, int>> voxels;
  for (const auto& b : boxes)
    for (int k = std::max(b.min.z, 0); k < std::min(b.min.z + b.size.z, int(g.dims.z) - 1); ++k)
      for (int j = std::max(b.min.y, 0); j < std::min(b.min.y + b.size.y, int(g.dims.y) - 1); ++j)
        for (int i = std::max(b.min.x, 0); i < std::min(b.min.x + b.size.x, int(g.dims.x) - 1); ++i) voxels.insert({i, j, k});
  return voxels;
}

double triangle_area(const TetMesh& m, const std::array<uint32_t, 3>& f) {
  return 0.5 * glm::length(glm::cross(m.points[f[1]] - m.points[f[0]], m.points[f[2]] - m.points[f[0]]));
}

// The region mesh is conforming (every triangle used by one or two cells) and is the union:
// its volume is the union's voxel count times a voxel's volume, and its boundary triangles'
// area is the union's surface area (a hanging vertex would leave a face used once inside,
// adding area). Boxes overlap, start off the lattice's zero, stick out of the grid, and one is
// twice the others' size.
TEST(RegionMesh, IsAConformingTetrahedralizationOfTheUnionOfBoxes) {
  volume::SampledGrid g = random_grid({21, 18, 14}, 5);
  const std::vector<volume::IndexBox> boxes = {
      {{-3, -3, -3}, {8, 8, 8}}, {{5, -3, -3}, {8, 8, 8}},  {{5, 5, -3}, {8, 8, 8}}, {{13, 5, 5}, {16, 16, 16}},
      {{5, 5, -3}, {8, 8, 8}},   {{-3, 13, 5}, {8, 8, 8}},  {{5, 5, 5}, {8, 8, 8}},
  };
  const TetMesh mesh = volume::make_region_mesh(g, boxes, 2.0);
  ASSERT_NO_THROW(validate(mesh));
  const auto voxels = union_voxels(g, boxes);
  const double voxel_volume = g.spacing.x * g.spacing.y * g.spacing.z;
  double volume = 0.0;
  for (const auto& t : mesh.tets) {
    const double v = signed_volume(mesh.points[t[0]], mesh.points[t[1]], mesh.points[t[2]], mesh.points[t[3]]);
    EXPECT_GT(v, 0.0);
    volume += v;
  }
  EXPECT_NEAR(volume, double(voxels.size()) * voxel_volume, 1e-9);
  double boundary = 0.0;
  for (const auto& [face, uses] : test::face_uses(mesh)) {
    EXPECT_TRUE(uses == 1 || uses == 2) << uses;
    if (uses == 1) boundary += triangle_area(mesh, face);
  }
  double surface = 0.0;
  const glm::dvec3 face_area(g.spacing.y * g.spacing.z, g.spacing.x * g.spacing.z, g.spacing.x * g.spacing.y);
  for (const auto& [i, j, k] : voxels)
    for (int a = 0; a < 3; ++a)
      for (int s : {-1, 1}) {
        glm::ivec3 n(i, j, k);
        n[a] += s;
        if (!voxels.count({n.x, n.y, n.z})) surface += face_area[a];
      }
  EXPECT_NEAR(boundary, surface, 1e-9);
  for (size_t i = 0; i < mesh.points.size(); ++i) {
    EXPECT_DOUBLE_EQ(mesh.point_scalars[i], volume::evaluate(g, mesh.points[i]));
    EXPECT_DOUBLE_EQ(mesh.point_extinction[i], std::max(2.0 * mesh.point_scalars[i], 0.0));
  }
}

TEST(RegionMesh, WholeGridIsOneKuhnCube) {
  const volume::SampledGrid g = random_grid({7, 3, 5}, 9);
  const TetMesh mesh = volume::make_region_mesh(g, volume::whole_grid(g));
  EXPECT_EQ(mesh.tets.size(), 6u);
  EXPECT_EQ(mesh.points.size(), 8u);
  const Bounds b = bounds_of(mesh), expected = volume::bounds_of(g);
  EXPECT_EQ(b.min, expected.min);
  EXPECT_EQ(b.max, expected.max);
}

// A block is kept when any sample its trilinear field depends on (its closed range, the next
// block's first samples included) is above the threshold: a single high sample on a block
// corner keeps all 8 blocks that share it, one inside a block keeps that block alone.
TEST(RegionMesh, BlocksAboveAThresholdKeepEveryBlockTouchingAHighSample) {
  volume::SampledGrid g;
  g.dims = {25, 25, 25};
  g.values.assign(25 * 25 * 25, 0.0f);
  g.values[g.index(8, 16, 8)] = 1.0f;   // a corner shared by blocks (0..1, 1..2, 0..1)
  g.values[g.index(19, 3, 21)] = 1.0f;  // inside block (2, 0, 2)
  const auto boxes = volume::blocks_above(g, 0.5);
  std::set<std::tuple<int, int, int>> got;
  for (const auto& b : boxes) {
    EXPECT_EQ(b.size, glm::ivec3(8));
    got.insert({b.min.x / 8, b.min.y / 8, b.min.z / 8});
  }
  std::set<std::tuple<int, int, int>> want = {{2, 0, 2}};
  for (int i : {0, 1})
    for (int j : {1, 2})
      for (int k : {0, 1}) want.insert({i, j, k});
  EXPECT_EQ(got, want);
  EXPECT_TRUE(volume::blocks_above(g, 1.0).empty());
  const TetMesh mesh = volume::make_region_mesh(g, boxes);
  EXPECT_EQ(mesh.tets.size(), 6u * want.size());
}

TEST(RegionMesh, EmptyBoxesAreRefused) {
  const volume::SampledGrid g = random_grid({4, 4, 4}, 1);
  EXPECT_THROW(volume::make_region_mesh(g, {{{0, 0, 0}, {0, 4, 4}}}), InputError);
  EXPECT_TRUE(volume::make_region_mesh(g, {{{10, 10, 10}, {4, 4, 4}}}).tets.empty());  // outside the grid: nothing
}

}  // namespace
}  // namespace prismoid
