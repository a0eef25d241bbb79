// Emission-absorption through a transfer function (beyond the paper): the GPU's composited
// colour against the CPU double-precision reference in exact per-pixel order.
//
// (Tolerances per pixel and channel: color_comparison.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/emission_absorption.hpp"
#include "scene/input_error.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "volume/color_comparison.hpp"

namespace prismoid {
namespace {

// On both interval backends (the compute backend orders each pixel itself: `ordering` is the
// mesh backend's). Comparison and tolerances: color_comparison.cpp.
class EmissionAbsorptionTest : public test::ColorTest {};

// What only the mesh backend has: draw orders, workgroup sizes, tetlets.
class EmissionAbsorptionMeshTest : public EmissionAbsorptionTest {};

const std::array<glm::dvec3, 4> kRegular = {glm::dvec3(1, 1, 1), glm::dvec3(1, -1, -1), glm::dvec3(-1, 1, -1), glm::dvec3(-1, -1, 1)};

TetMesh single_tet_with_scalars() {
  TetMesh m;
  m.name = "single tetrahedron";
  m.points.assign(kRegular.begin(), kRegular.end());
  m.tets = {{0, 1, 2, 3}};
  m.cell_extinction = {1.0};
  m.point_scalars = {0.0, 0.3, 0.7, 1.0};
  return m;
}

volume::TransferFunction test_tf(double density) {
  volume::TransferFunction tf = volume::preset("cool-to-warm");
  tf.opacity = {{0.0, 0.1}, {0.5, 0.9}, {1.0, 0.4}};
  tf.density_scale = density;
  return tf;
}

Camera looking_from(const glm::dvec3& eye, double near_distance = 0.05) {
  Camera c;
  c.eye = eye;
  c.target = glm::dvec3(0.0);
  c.up = std::abs(glm::normalize(eye).y) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  c.fovy_degrees = 50.0;
  c.near_distance = near_distance;
  return c;
}

TEST_P(EmissionAbsorptionTest, SingleTetrahedronWithLinearScalarMatchesReference) {
  for (const glm::dvec3 eye : {glm::dvec3(0.3, 0.2, 6.0), glm::normalize(kRegular[0]) * 6.0, glm::dvec3(-4.0, 2.5, 1.0)}) {
    const auto c = compare(single_tet_with_scalars(), test_tf(2.0), looking_from(eye), 48, 48, frame::Ordering::MeshOrder);
    EXPECT_GT(c.covered, 150u);
    EXPECT_EQ(c.failures, 0u) << c.first_failure;
  }
}

TEST_P(EmissionAbsorptionTest, NearClippedPiecesCompositeInOrder) {
  // The near plane splits the cell into three pieces whose segments along a ray must be
  // composited front to back; a linear scalar and a strongly varying transfer function make
  // any misordering visible.
  const glm::dvec3 v0 = glm::normalize(kRegular[0]);
  struct Case { const char* name; glm::dvec3 eye; double near_distance; };
  const Case cases[] = {{"one vertex behind", v0 * 6.0, 5.0}, {"two vertices behind", {0.0, 0.0, 3.0}, 3.0},
                        {"three vertices behind", -v0 * 6.0, 6.0}, {"eye inside", {0.1, -0.05, 0.2}, 0.02}};
  for (const auto& k : cases) {
    Camera camera = looking_from(k.eye, k.near_distance);
    camera.fovy_degrees = 70.0;
    if (k.name == std::string("eye inside")) camera.target = glm::dvec3(0.3, 0.2, -1.0);
    const auto c = compare(single_tet_with_scalars(), test_tf(4.0), camera, 40, 40, frame::Ordering::MeshOrder);
    EXPECT_GT(c.covered, 30u) << k.name;
    EXPECT_EQ(c.failures, 0u) << k.name << ": " << c.first_failure;
  }
}

TEST_P(EmissionAbsorptionTest, CellScalarsAreConstantPerCell) {
  TetMesh mesh = single_tet_with_scalars();
  mesh.point_scalars.clear();
  mesh.cell_scalars = {0.6};
  const auto c = compare(mesh, test_tf(3.0), looking_from({0.3, 0.2, 6.0}), 40, 40, frame::Ordering::MeshOrder);
  EXPECT_GT(c.covered, 200u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TetMesh default_with_scalars() {
  TetMesh mesh = make_default_volume();  // point_scalars: the Gaussian blobs' density
  return mesh;
}

volume::TransferFunction blob_tf() {
  volume::TransferFunction tf = volume::preset("viridis");
  tf.opacity = {{0.0, 0.0}, {0.2, 0.3}, {0.6, 0.8}, {1.0, 1.0}};
  tf.range_lo = 0.0;
  tf.range_hi = 6.0;
  tf.density_scale = 25.0;  // optical depths of several units: order matters
  return tf;
}

// The default dataset is a Kuhn-split box: convex, and its visibility graph is acyclic, so
// the topological order is exact for every ray and the GPU must match the reference.
TEST_P(EmissionAbsorptionTest, ExactOrderOnConvexMeshMatchesReference) {
  const TetMesh mesh = default_with_scalars();
  Camera outside = fit_camera(bounds_of(mesh));
  outside.eye = outside.target + glm::dvec3(2.0, 1.5, 4.5);
  Camera inside;
  inside.eye = {0.13, 0.07, 0.21};
  inside.target = {1.0, 0.5, -2.0};
  inside.fovy_degrees = 70.0;
  inside.near_distance = 0.01;
  for (const Camera& camera : {outside, inside}) {
    const auto c = compare(mesh, blob_tf(), camera, 40, 30, frame::Ordering::Exact);
    EXPECT_TRUE(c.order_exact) << c.ordering;
    EXPECT_GT(c.covered, 300u);
    EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
    std::printf("exact order: max error %.3g, rmse %.3g, worst pixel at %.2f of its tolerance\n", c.max_error, c.rmse,
                c.worst_over_tolerance);
    ::testing::Test::RecordProperty("exact_order_max_error", std::to_string(c.max_error));
    if (compute()) continue;  // the compute backend has no mesh order; the tolerance's power is the same
    const auto unsorted = compare(mesh, blob_tf(), camera, 40, 30, frame::Ordering::MeshOrder);
    std::printf("  mesh order: max error %.3g, %zu pixels beyond tolerance\n", unsorted.max_error, unsorted.failures);
    EXPECT_GT(unsorted.failures, 0u) << "the tolerance cannot tell a wrong order from the right one";
  }
}

// Opaque geometry inside the volume (a slice through it, in the left half of the image) ends the
// rays there: both backends clip each interval at the pixel's depth limit as the reference ends
// its rays, within the same tolerances.
TEST_P(EmissionAbsorptionTest, RaysEndAtTheDepthLimitAsInTheReference) {
  const TetMesh mesh = default_with_scalars();
  Camera camera = fit_camera(bounds_of(mesh));
  camera.eye = camera.target + glm::dvec3(2.0, 1.5, 4.5);
  const uint32_t w = 40, h = 30;
  // The depth, along the viewing axis, of the data's centre: the slice halves the volume there.
  const float middle = float(glm::length(camera.target - camera.eye));
  auto limit = std::make_shared<std::vector<float>>(size_t(w) * h, std::numeric_limits<float>::infinity());
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w / 2; ++x) (*limit)[size_t(y) * w + x] = middle;
  const auto c = compare(mesh, blob_tf(), camera, w, h, frame::Ordering::Exact, 0, std::nullopt, limit);
  EXPECT_GT(c.covered, 300u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
  // The limit changes the image where it lies (so the comparison can tell), and only there.
  const auto cut = reference::emission_absorption_image(mesh, blob_tf(), camera, w, h, 0.0, 0.0, nullptr, nullptr, limit.get());
  const auto whole = reference::emission_absorption_image(mesh, blob_tf(), camera, w, h);
  double left = 0.0, right = 0.0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const double d = std::abs(cut.pixels[i].a - whole.pixels[i].a);
      (x < w / 2 ? left : right) = std::max(x < w / 2 ? left : right, d);
    }
  EXPECT_GT(left, 0.05) << "the slice should hide a visible part of the volume";
  EXPECT_EQ(right, 0.0);
  std::printf("depth limit: max error %.3g, the slice changes alpha by up to %.3f\n", c.max_error, left);
}

// A field of view of 1e-6 degrees: the camera framing the data stands 2e8 from it, where floats
// are 16 apart. Each segment's ends and scalars come relative to its cell (interval_ray.glsl),
// so the composited colour in exact order still matches the reference (depths themselves are
// 16 apart there: differences of them are no lengths).
TEST_P(EmissionAbsorptionTest, MicroDegreeFieldOfViewMatchesReferenceInExactOrder) {
  const TetMesh mesh = default_with_scalars();
  const Camera camera = fit_camera(bounds_of(mesh), 1e-6);
  ASSERT_GT(glm::length(camera.eye - camera.target), 1e8);
  const auto c = compare(mesh, blob_tf(), camera, 40, 30, frame::Ordering::Exact);
  EXPECT_TRUE(c.order_exact) << c.ordering;
  EXPECT_GT(c.covered, 200u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
  std::printf("fovy 1e-6, exact order: max error %.3g, worst pixel at %.2f of its tolerance\n", c.max_error, c.worst_over_tolerance);
}

// One cell 10^6 tall seen from beside it: its faces project to long slivers whose areas are
// tiny next to the square of the cell's projected size; every face still votes with its sign
// (tet_projection.glsl), so the colour matches the reference.
TEST_P(EmissionAbsorptionTest, CellAMillionTimesTallerThanWideMatchesReference) {
  TetMesh mesh = single_tet_with_scalars();
  mesh.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1e6}};
  Camera camera;
  camera.eye = {0.2, -5.0, 0.5};
  camera.target = {0.2, 0.0, 0.5};
  camera.up = {0.0, 0.0, 1.0};
  camera.near_distance = 0.01;
  const auto c = compare(mesh, test_tf(2.0), camera, 48, 48, frame::Ordering::Exact);
  EXPECT_GT(c.covered, 150u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
}

// Beyond float: an extinction of 1e300 at opacity 1 (stored up to volume::extinction_cap: every
// segment the GPU can resolve is opaque either way), and a range of -1e300..1e300 (mapped as
// x = s * scale + offset with both rounded once: scale is 0 in float and every value lands at
// 0.5, as in double; (s - lo) / width with float(lo) = -inf would give inf * 0).
TEST_P(EmissionAbsorptionTest, ExtinctionAndRangeBeyondFloatMatchReference) {
  const TetMesh mesh = default_with_scalars();
  Camera camera = fit_camera(bounds_of(mesh));
  camera.eye = camera.target + glm::dvec3(2.0, 1.5, 4.5);
  volume::TransferFunction dense = blob_tf();
  dense.density_scale = 1e300;
  volume::TransferFunction wide = blob_tf();
  wide.range_lo = -1e300;
  wide.range_hi = 1e300;
  for (const auto& tf : {dense, wide}) {
    const auto c = compare(mesh, tf, camera, 40, 30, frame::Ordering::Exact);
    EXPECT_GT(c.covered, 300u);
    EXPECT_EQ(c.failures, 0u) << "density " << tf.density_scale << ", range " << tf.range_lo << ".." << tf.range_hi << ": "
                              << c.first_failure << " (max error " << c.max_error << ")";
  }
}

// Sorting by centroid distance is an approximation (a cell can be nearer by centroid yet
// behind along some rays); it must still beat drawing in mesh order, and the sort must run
// as its own timed pass.
TEST_P(EmissionAbsorptionMeshTest, GpuSortIsCloserThanMeshOrderAndRunsAsAPass) {
  const TetMesh mesh = default_with_scalars();
  Camera camera = fit_camera(bounds_of(mesh));
  camera.eye = camera.target + glm::dvec3(-3.0, 2.0, -3.5);  // mesh order is far from back to front here
  const auto sorted = compare(mesh, blob_tf(), camera, 40, 30, frame::Ordering::GpuSort);
  const auto unsorted = compare(mesh, blob_tf(), camera, 40, 30, frame::Ordering::MeshOrder);
  EXPECT_NE(std::find(sorted.passes.begin(), sorted.passes.end(), "sort"), sorted.passes.end());
  EXPECT_EQ(std::find(unsorted.passes.begin(), unsorted.passes.end(), "sort"), unsorted.passes.end());
  EXPECT_FALSE(sorted.order_exact);
  EXPECT_LT(sorted.rmse, 0.5 * unsorted.rmse);
  std::printf("gpu sort: rmse %.3g (max %.3g); mesh order: rmse %.3g (max %.3g)\n", sorted.rmse, sorted.max_error,
              unsorted.rmse, unsorted.max_error);
}

TEST_P(EmissionAbsorptionTest, OrderIndependentQuantitiesNeverSort) {
  const TetMesh mesh = default_with_scalars();
  frame::FrameRenderer renderer(device(), mesh);
  frame::FrameSettings settings = settings_on_backend();
  settings.resolve.quantity = volume::Quantity::OpticalDepth;
  settings.ordering = frame::Ordering::GpuSort;
  const auto frame = renderer.render_offscreen(fit_camera(bounds_of(mesh)), settings, {16, 16});
  for (const auto& p : frame.passes) EXPECT_NE(p.name, "sort");
  EXPECT_EQ(frame.report.ordering, "none (order-independent)");
}

// Cells per mesh workgroup changes how work is grouped, not which primitives are drawn or in
// what order (workgroups in order, primitives in order within each), so additive and
// front-to-back blending see the same sequence: the images are bit-identical.
TEST_P(EmissionAbsorptionMeshTest, TetletSizesGiveBitIdenticalImages) {
  const TetMesh mesh = default_with_scalars();
  Camera camera;
  camera.eye = {0.13, 0.07, 0.21};  // inside: clipped cells emit up to 15 vertices each
  camera.target = {1.0, 0.5, -2.0};
  camera.fovy_degrees = 70.0;
  camera.near_distance = 0.01;
  frame::FrameRenderer renderer(device(), mesh);
  for (const auto quantity : {volume::Quantity::OpticalDepth, volume::Quantity::Color}) {
    frame::FrameSettings settings;
    settings.resolve.quantity = quantity;
    settings.resolve.transfer = blob_tf();
    settings.ordering = frame::Ordering::GpuSort;
    std::vector<float> first;
    for (uint32_t size : volume::kTetletSizes) {
      settings.resolve.tetlet_size = size;
      const auto f = renderer.render_offscreen(camera, settings, {32, 24});
      const auto& image = quantity == volume::Quantity::Color ? f.emission : f.quantity;
      if (first.empty()) first = image;
      else EXPECT_EQ(image, first) << "tetlet size " << size;
    }
  }
}

// Tetlets load each shared point once and draw cells tetlet by tetlet; every cell still gets
// the same camera-space corners and so the same fragments, only summed in another order. Each
// additive blend rounds by at most 2^-24 of the running sum, so two orders of n terms differ
// by at most 2 n 2^-24 of the pixel's optical depth (here n < 100 segments).
TEST_P(EmissionAbsorptionMeshTest, TetletsWithSharedPointsGiveTheSameOpticalDepth) {
  TetMesh mesh = default_with_scalars();
  mesh.point_extinction = mesh.point_scalars;  // per-point fields go through shared memory too
  Camera inside;
  inside.eye = {0.13, 0.07, 0.21};
  inside.target = {1.0, 0.5, -2.0};
  inside.fovy_degrees = 70.0;
  inside.near_distance = 0.01;
  Camera outside = fit_camera(bounds_of(mesh));
  outside.eye = outside.target + glm::dvec3(2.0, 1.5, 4.5);
  frame::FrameRenderer renderer(device(), mesh);
  for (const Camera& camera : {outside, inside})
    for (uint32_t size : {4u, 8u, 16u}) {
      frame::FrameSettings settings;
      settings.resolve.quantity = volume::Quantity::OpticalDepth;
      settings.resolve.tetlet_size = size;
      const auto cells = renderer.render_offscreen(camera, settings, {40, 30});
      settings.resolve.shared_vertices = true;
      const auto tetlets = renderer.render_offscreen(camera, settings, {40, 30});
      EXPECT_LE(tetlets.report.tetlet_points_per_cell, 2.0);  // 4 without sharing
      double covered = 0.0;
      for (size_t i = 0; i < cells.quantity.size(); ++i) {
        EXPECT_TRUE(std::isfinite(tetlets.quantity[i]));
        EXPECT_NEAR(tetlets.quantity[i], cells.quantity[i], 2.0 * 100.0 * std::ldexp(1.0, -24) * double(cells.quantity[i]) + 1e-30)
            << "tetlet size " << size << ", pixel " << i;
        covered += cells.quantity[i] > 0.0f ? 1.0 : 0.0;
      }
      EXPECT_GT(covered, 300.0);
    }
}

TEST_P(EmissionAbsorptionTest, PreintegratedTableMatchesReferenceWithTheSameTable) {
  // Unclipped cells only: a table's lookups do not add up along a ray like the exact integral
  // does, so a cell split by the near plane differs from the reference's single lookup by the
  // table's error (measured by the bench, not a GPU error).
  for (uint32_t size : {8u, 32u}) {
    const auto c = compare(single_tet_with_scalars(), test_tf(2.0), looking_from({0.3, 0.2, 6.0}), 40, 40,
                           frame::Ordering::MeshOrder, size);
    EXPECT_GT(c.covered, 150u);
    EXPECT_EQ(c.failures, 0u) << size << ": " << c.first_failure;
  }
}

PRISMOID_ON_BOTH_BACKENDS(EmissionAbsorptionTest);
PRISMOID_ON_MESH_BACKEND(EmissionAbsorptionMeshTest);

}  // namespace
}  // namespace prismoid
