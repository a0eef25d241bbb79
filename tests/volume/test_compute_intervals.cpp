// What only the compute interval backend has (renderer/volume/compute/compute_intervals.hpp): its
// passes and memory, tiles holding more cells than a workgroup sets up at once, pixels with
// more intervals than their k-buffer, a cell covering the whole screen, a million cells, a
// non-convex mesh whose topological order cannot be exact, and buffers that grow. Every image
// is compared with the CPU reference within the tolerances the shared tests derive
// (interval_comparison.cpp for optical depth, color_comparison.cpp for colour).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <glm/trigonometric.hpp>
#include <string>
#include <vector>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/volume/compute/compute_intervals.hpp"
#include "renderer/volume/visibility_order.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"
#include "volume/color_comparison.hpp"
#include "volume/interval_comparison.hpp"

namespace prismoid {
namespace {

class ComputeIntervalsTest : public test::IntervalShadingTest {};

std::vector<std::string> names(const std::vector<vk::PassTiming>& passes) {
  std::vector<std::string> v;
  for (const auto& p : passes) v.push_back(p.name);
  return v;
}

Camera looking_at(const glm::dvec3& eye, const glm::dvec3& target, double fovy = 40.0, double near_distance = 0.05) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = glm::dvec3(0, 1, 0);
  c.fovy_degrees = fovy;
  c.near_distance = near_distance;
  return c;
}

volume::TransferFunction ramp_tf(double density) {
  volume::TransferFunction tf = volume::preset("viridis");
  tf.opacity = {{0.0, 0.2}, {0.5, 0.6}, {1.0, 0.9}};
  tf.density_scale = density;
  return tf;
}

// `count` thin cells stacked along the view axis (the eye at z = 5 looking down -z), cell i a
// triangle at z = 1 - i * spacing (depth 4 + i * spacing) widened to a tetrahedron by a
// fourth point to the side at z = apex_z(i). Its depth key is its nearest point's depth:
// with the apex a little behind the triangle the keys follow the cells' order along the axis;
// with the apexes rising (nearer the eye) as i grows they come in the reverse order, which
// no k-buffer of 8 entries can put right. Scalars per cell ramp along the stack, so a wrong
// order shows in the colour.
template <typename ApexZ>
TetMesh stack(uint32_t count, double spacing, ApexZ apex_z) {
  TetMesh mesh;
  mesh.name = "stack";
  for (uint32_t i = 0; i < count; ++i) {
    const double z = 1.0 - i * spacing;
    const auto base = static_cast<uint32_t>(mesh.points.size());
    mesh.points.push_back({-0.6, -0.5, z});
    mesh.points.push_back({0.6, -0.5, z});
    mesh.points.push_back({0.0, 0.7, z});
    mesh.points.push_back({2.5, 0.1, apex_z(i, z)});
    mesh.tets.push_back({base, base + 1, base + 2, base + 3});
    mesh.cell_extinction.push_back(0.5);
    mesh.cell_scalars.push_back(double(i) / double(count - 1));
  }
  return mesh;
}

// A torus of square cross-section about the z axis (ring radius r, cross-section half width
// w), `around` segments of 2 x 2 Kuhn-split cubes, moved by `place`. The segments close up, so
// the cells share faces all around.
template <typename Place>
void add_torus(TetMesh& mesh, double r, double w, uint32_t around, Place place) {
  const uint32_t n = 2, m = n + 1;
  const auto base = static_cast<uint32_t>(mesh.points.size());
  auto index = [&](uint32_t i, uint32_t j, uint32_t k) { return base + ((i % around) * m + j) * m + k; };
  for (uint32_t i = 0; i < around; ++i) {
    const double theta = 2.0 * M_PI * i / around;
    for (uint32_t j = 0; j < m; ++j)
      for (uint32_t k = 0; k < m; ++k) {
        const double radial = r + w * (2.0 * j / n - 1.0), height = w * (2.0 * k / n - 1.0);
        mesh.points.push_back(place(glm::dvec3(radial * std::cos(theta), radial * std::sin(theta), height)));
        mesh.point_scalars.push_back(0.5 + 0.5 * std::sin(3.0 * theta + height / w));
      }
  }
  static const uint32_t kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (uint32_t i = 0; i < around; ++i)
    for (uint32_t j = 0; j < n; ++j)
      for (uint32_t k = 0; k < n; ++k)
        for (const auto& path : kPaths) {
          uint32_t c[3] = {i, j, k};
          std::array<uint32_t, 4> tet;
          tet[0] = index(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[path[s]];
            tet[s + 1] = index(c[0], c[1], c[2]);
          }
          const auto& p = mesh.points;
          if (signed_volume(p[tet[0]], p[tet[1]], p[tet[2]], p[tet[3]]) < 0.0) std::swap(tet[2], tet[3]);
          mesh.tets.push_back(tet);
          mesh.cell_extinction.push_back(1.0);
        }
}

// Two tori linked like chain links: the second about the x axis, through the first's hole.
TetMesh interlocking_tori() {
  TetMesh mesh;
  mesh.name = "interlocking tori";
  add_torus(mesh, 1.0, 0.25, 24, [](const glm::dvec3& p) { return p; });
  add_torus(mesh, 1.0, 0.25, 24, [](const glm::dvec3& p) { return glm::dvec3(p.x + 1.0, p.z, p.y); });
  return mesh;
}

TEST_P(ComputeIntervalsTest, FramesRecordThePlannedPassesAndReportTheirMemory) {
  const TetMesh mesh = make_default_volume();
  const Camera camera = looking_at({2.0, 1.5, 4.5}, glm::dvec3(0.0));
  frame::FrameRenderer compute(device(), mesh);
  const auto frame = compute.render_offscreen(camera, settings_on_backend(), {40, 30});
  const std::vector<std::string> passes = {"bin-cells", "tile-sort", "tile-raster", "resolve"};
  EXPECT_EQ(names(frame.passes), passes);
  EXPECT_EQ(frame.report.plan.gpu_pass_names(), passes);
  EXPECT_EQ(frame.report.backend, "compute");
  ASSERT_NE(compute.compute_intervals(), nullptr);
  EXPECT_EQ(frame.report.backend_bytes, compute.compute_intervals()->bytes());
  const uint64_t tiles = 5 * 4;
  EXPECT_GE(frame.report.backend_bytes, volume::ComputeIntervals::bytes_for(mesh.tets.size(), tiles, frame.report.pairs));
  EXPECT_TRUE(frame.report.counts_known);
  EXPECT_GT(frame.report.pairs, mesh.tets.size() / 2);  // most cells are seen, each in a tile or more

  frame::FrameRenderer mesh_shader(device(), mesh);
  frame::FrameSettings settings;
  const auto mesh_frame = mesh_shader.render_offscreen(camera, settings, {40, 30});
  EXPECT_EQ(mesh_frame.report.backend, "mesh");
  EXPECT_EQ(mesh_frame.report.backend_bytes, 0u);
  EXPECT_EQ(mesh_shader.compute_intervals(), nullptr) << "the compute backend was made for a mesh-shader frame";
}

// Each pixel's sum is formed by one invocation, over its tile's cells in sorted order: two
// renderers give the same bits.
TEST_P(ComputeIntervalsTest, ImagesAreBitIdenticalFromRunToRun) {
  const TetMesh mesh = make_default_volume();
  const Camera camera = looking_at({0.13, 0.07, 0.21}, {1.0, 0.5, -2.0}, 70.0, 0.01);
  frame::FrameSettings settings = settings_on_backend();
  settings.resolve.quantity = volume::Quantity::Color;
  settings.resolve.transfer = ramp_tf(20.0);
  settings.resolve.transfer.range_hi = 6.0;
  for (const auto quantity : {volume::Quantity::OpticalDepth, volume::Quantity::Color}) {
    settings.resolve.quantity = quantity;
    frame::FrameRenderer a(device(), mesh), b(device(), mesh);
    const auto fa = a.render_offscreen(camera, settings, {37, 29}), fb = b.render_offscreen(camera, settings, {37, 29});
    EXPECT_EQ(fa.quantity, fb.quantity);
    EXPECT_EQ(fa.display, fb.display);
    EXPECT_EQ(fa.emission, fb.emission);
  }
}

// 100 cells stacked on the same pixels: a tile holds more cells than a workgroup sets up at
// once (64), and each pixel more intervals than its k-buffer (8), arriving nearly in depth
// order, so the k-buffer composites them all in exact order.
TEST_P(ComputeIntervalsTest, TilesWithMoreCellsThanAWorkgroupHoldsStayExact) {
  const TetMesh mesh = stack(100, 0.02, [](uint32_t, double z) { return z - 0.01; });
  const Camera camera = looking_at({0.0, 0.0, 5.0}, glm::dvec3(0.0), 30.0);
  const auto depth = compare(mesh, camera, 32, 32);
  EXPECT_GT(depth.covered, 200u);
  EXPECT_EQ(depth.failures, 0u) << depth.first_failure;
  const auto colour = test::ColorTest::compare(mesh, ramp_tf(2.0), camera, 32, 32, frame::Ordering::Exact);
  EXPECT_GT(*std::max_element(colour.segments.begin(), colour.segments.end()), 64u);
  EXPECT_EQ(colour.report.inexact_pixels, 0u);
  EXPECT_TRUE(colour.order_exact) << colour.ordering;
  EXPECT_EQ(colour.failures, 0u) << colour.first_failure;
}

// 5000 cells stacked on the same pixels: each tile's list is longer than a chunk (512 pairs for
// optical depth, 4096 for colour), so workgroups of their own raster its chunks and a merge
// combines them. The keys follow the cells' order along the axis, so each pixel's intervals
// stay in order across chunks: the merged colour is exact, and the optical depth (a sum) too.
TEST_P(ComputeIntervalsTest, LongTileListsAreRasteredInChunksAndMergedExactly) {
  const TetMesh mesh = stack(5000, 0.00015, [](uint32_t, double z) { return z - 0.00007; });
  const Camera camera = looking_at({0.0, 0.0, 5.0}, glm::dvec3(0.0), 30.0);
  frame::FrameRenderer renderer(device(), mesh);
  frame::FrameSettings settings = settings_on_backend();
  settings.resolve.quantity = volume::Quantity::OpticalDepth;
  const auto frame = renderer.render_offscreen(camera, settings, {24, 24});
  EXPECT_GT(frame.report.split_tiles, 0u);
  EXPECT_GE(frame.report.chunks, 10 * frame.report.split_tiles) << "5000 pairs make ten chunks of at most 512";
  const auto depth = compare_image(frame.quantity, mesh, camera, 24, 24);
  EXPECT_GT(depth.covered, 150u);
  EXPECT_EQ(depth.failures, 0u) << depth.first_failure;
  const auto colour = test::ColorTest::compare(mesh, ramp_tf(2.0), camera, 24, 24, frame::Ordering::Exact);
  EXPECT_GT(colour.report.split_tiles, 0u);
  EXPECT_GE(colour.report.chunks, 2 * colour.report.split_tiles) << "5000 pairs make two chunks of at most 4096";
  EXPECT_EQ(colour.report.inexact_pixels, 0u);
  EXPECT_EQ(colour.failures, 0u) << colour.first_failure << " (max error " << colour.max_error << ")";
}

// An 8x8 image is one tile: its whole list (every cell of a 10,368-cell box) is split into chunks
// across workgroups. Optical depth (a sum) matches the reference. In colour some pixel's
// intervals cross from one chunk into an earlier one's depths: the merge sends the tile back to
// be rastered whole, so colour matches too, with no pixel composited out of order.
TEST_P(ComputeIntervalsTest, AOneTileImageSplitsItsListAcrossWorkgroups) {
  const TetMesh mesh = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 12, [](const glm::dvec3& p) {
    return 0.6 + 0.3 * std::sin(2.0 * p.x) * std::cos(1.5 * p.y) + 0.2 * p.z;
  });
  const Camera camera = looking_at({1.1, 0.8, 1.9}, glm::dvec3(0.0), 45.0);
  const auto depth = compare(mesh, camera, 8, 8);
  EXPECT_EQ(depth.covered, 64u);
  EXPECT_EQ(depth.failures, 0u) << depth.first_failure;
  const auto colour = test::ColorTest::compare(mesh, ramp_tf(1.0), camera, 8, 8, frame::Ordering::Exact);
  EXPECT_EQ(colour.report.split_tiles, 1u);
  EXPECT_GE(colour.report.chunks, mesh.tets.size() / 4096);
  EXPECT_EQ(colour.report.inexact_pixels, 0u);
  EXPECT_EQ(colour.failures, 0u) << colour.first_failure << " (max error " << colour.max_error << ")";
}

// A colour whose per-pixel order crosses a chunk boundary: the 4200-cell stack plus one cell
// whose nearest corner lies far to the side, in front of the whole stack (its depth key sorts
// it first, into the first chunk), while over the middle of the view it lies behind the whole
// stack, so the second chunk's intervals there are nearer than one the first chunk composited.
// The merge sends those tiles back to be rastered whole: the colour matches the reference.
TEST_P(ComputeIntervalsTest, AColourOrderCrossingChunksIsRasteredAgainWhole) {
  TetMesh mesh = stack(4200, 0.00015, [](uint32_t, double z) { return z - 0.00007; });
  const auto base = static_cast<uint32_t>(mesh.points.size());
  mesh.points.insert(mesh.points.end(), {{-3.0, 0.0, 1.0}, {-0.5, -0.5, -0.9}, {0.5, -0.5, -0.9}, {0.0, 0.6, -0.9}});
  mesh.tets.push_back({base, base + 1, base + 2, base + 3});
  mesh.cell_extinction.push_back(0.5);
  mesh.cell_scalars.push_back(0.3);
  const Camera camera = looking_at({0.0, 0.0, 5.0}, glm::dvec3(0.0), 30.0);
  const auto colour = test::ColorTest::compare(mesh, ramp_tf(2.0), camera, 24, 24, frame::Ordering::Exact);
  EXPECT_GT(colour.report.split_tiles, 0u);
  EXPECT_GT(colour.report.redone_tiles, 0u) << "no pixel's order crossed a chunk boundary: the test cannot tell";
  EXPECT_EQ(colour.report.inexact_pixels, 0u);
  EXPECT_EQ(colour.failures, 0u) << colour.first_failure << " (max error " << colour.max_error << ")";
  std::printf("order across chunks: %llu of %llu split tiles rastered again whole\n",
              static_cast<unsigned long long>(colour.report.redone_tiles), static_cast<unsigned long long>(colour.report.split_tiles));
}

// The same stack with its depth keys in reverse order along the axis: where more than 8
// intervals arrive out of order the k-buffer cannot restore it. Those pixels are counted; the
// opacity (alpha = 1 - transmittance, a product, so order-free) stays exact everywhere, and
// the colour strays only at pixels the count covers. Optical depth is a sum: exact.
TEST_P(ComputeIntervalsTest, IntervalsBeyondTheKBufferAreCountedAndOnlyTheirColourStrays) {
  const uint32_t count = 20;
  const TetMesh mesh = stack(count, 0.1, [](uint32_t i, double) { return 2.0 + 0.1 * i; });
  const Camera camera = looking_at({0.0, 0.0, 5.0}, glm::dvec3(0.0), 30.0);
  const auto depth = compare(mesh, camera, 32, 32);
  EXPECT_GT(depth.covered, 200u);
  EXPECT_EQ(depth.failures, 0u) << depth.first_failure;
  const auto colour = test::ColorTest::compare(mesh, ramp_tf(2.0), camera, 32, 32, frame::Ordering::Exact);
  size_t deep = 0, colour_failed = 0, alpha_failed = 0;
  for (size_t i = 0; i < colour.segments.size(); ++i) {
    deep += colour.segments[i] > volume::ComputeIntervals::kKBuffer ? 1 : 0;
    colour_failed += colour.colour_failed[i] ? 1 : 0;
    alpha_failed += colour.alpha_failed[i] ? 1 : 0;
  }
  EXPECT_GT(colour.report.inexact_pixels, 0u);
  EXPECT_LE(colour.report.inexact_pixels, deep) << "only a pixel with more intervals than its k-buffer can overflow";
  EXPECT_FALSE(colour.order_exact);
  EXPECT_EQ(alpha_failed, 0u);
  EXPECT_LE(colour_failed, colour.report.inexact_pixels);
  EXPECT_GT(colour_failed, 0u) << "the reversed order was not visible: the test cannot tell";
  std::printf("reversed stack: %llu inexact pixels of %zu with more than %u intervals; %zu beyond the colour tolerance\n",
              static_cast<unsigned long long>(colour.report.inexact_pixels), deep, volume::ComputeIntervals::kKBuffer,
              colour_failed);
}

// One cell covering every pixel: seen from inside, and from just in front of a face.
TEST_P(ComputeIntervalsTest, ACellCoveringTheWholeScreenMatchesTheReference) {
  TetMesh mesh;
  mesh.name = "one big cell";
  mesh.points = {{100, 100, 100}, {100, -100, -100}, {-100, 100, -100}, {-100, -100, 100}};
  mesh.tets = {{0, 1, 2, 3}};
  mesh.cell_extinction = {0.02};
  mesh.point_scalars = {0.0, 0.4, 0.8, 1.0};
  const glm::dvec3 face_centre = (mesh.points[1] + mesh.points[2] + mesh.points[3]) / 3.0;
  const Camera inside = looking_at({1.0, 2.0, -3.0}, {20.0, -10.0, 5.0}, 70.0, 0.05);
  const Camera outside = looking_at(face_centre * 1.05, glm::dvec3(0.0), 60.0, 0.05);
  for (const Camera& camera : {inside, outside}) {
    const auto depth = compare(mesh, camera, 48, 40);
    EXPECT_EQ(depth.covered, 48u * 40u);
    EXPECT_EQ(depth.failures, 0u) << depth.first_failure;
    const auto colour = test::ColorTest::compare(mesh, ramp_tf(0.05), camera, 48, 40, frame::Ordering::Exact);
    EXPECT_EQ(colour.covered, 48u * 40u);
    EXPECT_EQ(colour.failures, 0u) << colour.first_failure;
  }
}

// Two linked tori: not convex, so the topological order over face adjacency cannot be exact
// for every ray (it says so); each pixel's own order is.
TEST_P(ComputeIntervalsTest, InterlockingToriInEachPixelsOwnOrderMatchTheReference) {
  const TetMesh mesh = interlocking_tori();
  ASSERT_EQ(mesh.tets.size(), 2u * 24u * 4u * 6u);
  const Camera camera = looking_at({0.9, 2.6, 3.1}, {0.5, 0.0, 0.0}, 55.0);
  const volume::VisibilityOrder order = volume::exact_order(mesh, volume::build_adjacency(mesh), camera.eye);
  EXPECT_FALSE(order.exact) << "the topological order would be exact here: the test cannot tell";
  const auto colour = test::ColorTest::compare(mesh, ramp_tf(3.0), camera, 48, 40, frame::Ordering::Exact);
  EXPECT_GT(colour.covered, 400u);
  EXPECT_EQ(colour.report.inexact_pixels, 0u);
  EXPECT_TRUE(colour.order_exact) << colour.ordering;
  EXPECT_EQ(colour.failures, 0u) << colour.first_failure << " (max error " << colour.max_error << ")";
  std::printf("interlocking tori: %s; max error %.3g, worst pixel at %.2f of its tolerance\n",
              order.acyclic ? "acyclic, not convex" : "cyclic", colour.max_error, colour.worst_over_tolerance);
}

// Three long thin cells along the sides of a triangle, each rising from one corner to the next,
// so seen from above stick k lies over stick k + 1 where they cross: a cyclic 'in front of'
// relation (as in test_visibility_order.cpp) that no order of the cells satisfies. The mesh
// backend, drawing the cells in any one order, is wrong at a crossing (the tolerance tells);
// each pixel's own order is right.
TEST_P(ComputeIntervalsTest, CyclicallyOverlappingCellsInEachPixelsOwnOrderMatchTheReference) {
  TetMesh mesh;
  mesh.name = "sticks";
  glm::dvec3 corner[3];
  for (int k = 0; k < 3; ++k) corner[k] = glm::dvec3(std::cos(2 * M_PI * k / 3), std::sin(2 * M_PI * k / 3), 0.0);
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 from = corner[k], to = corner[(k + 1) % 3];
    from.z = -0.5, to.z = 0.5;
    const glm::dvec3 start = from - 0.2 * (to - from), end = to + 0.2 * (to - from);
    const glm::dvec3 across = glm::normalize(glm::cross(to - from, glm::dvec3(0, 0, 1))) * 0.1, up(0.0, 0.0, 0.1);
    const auto base = static_cast<uint32_t>(mesh.points.size());
    mesh.points.insert(mesh.points.end(), {start + across, start - across, end + up, end - up});
    mesh.tets.push_back({base, base + 1, base + 2, base + 3});
    mesh.cell_extinction.push_back(1.0);
    mesh.cell_scalars.push_back(0.5 * k);
  }
  const Camera camera = looking_at({0.1, 0.05, 3.0}, glm::dvec3(0.0), 50.0);
  const auto colour = test::ColorTest::compare(mesh, ramp_tf(30.0), camera, 64, 64, frame::Ordering::Exact);
  EXPECT_GT(colour.covered, 300u);
  EXPECT_EQ(colour.report.inexact_pixels, 0u);
  EXPECT_EQ(colour.failures, 0u) << colour.first_failure << " (max error " << colour.max_error << ")";
  for (const frame::Ordering ordering : {frame::Ordering::Exact, frame::Ordering::GpuSort, frame::Ordering::MeshOrder}) {
    const auto ordered = test::ColorTest::compare(mesh, ramp_tf(30.0), camera, 64, 64, ordering, 0, frame::IntervalBackend::Mesh);
    EXPECT_GT(ordered.failures, 0u) << frame::ordering_name(ordering) << " drew the cycle right: the test cannot tell";
    std::printf("sticks, mesh backend, %s: %zu channels beyond tolerance, max error %.3g\n", frame::ordering_name(ordering),
                ordered.failures, ordered.max_error);
  }
}

// 1100 screen-filling cells at 64x64 (64 tiles) need 70,400 pairs, more than the first
// guess of 65,536: the frame that asked for them is drawn again with room for all.
TEST_P(ComputeIntervalsTest, PairsBeyondTheFirstGuessGrowAndTheFrameIsDrawnWhole) {
  TetMesh mesh;
  mesh.name = "screen-filling slabs";
  for (uint32_t i = 0; i < 1100; ++i) {
    const double z = -1.0 - 0.01 * i;
    const auto base = static_cast<uint32_t>(mesh.points.size());
    mesh.points.insert(mesh.points.end(), {{-50, -50, z}, {50, -50, z}, {0, 60, z}, {0, 0, z - 0.005}});
    mesh.tets.push_back({base, base + 1, base + 2, base + 3});
    mesh.cell_extinction.push_back(0.3);
  }
  const Camera camera = looking_at({0.0, 0.0, 1.0}, {0.0, 0.0, -1.0}, 40.0);
  frame::FrameRenderer renderer(device(), mesh);
  frame::FrameSettings settings = settings_on_backend();
  settings.resolve.quantity = volume::Quantity::OpticalDepth;
  const auto frame = renderer.render_offscreen(camera, settings, {64, 64});
  EXPECT_EQ(frame.report.pairs, 1100u * 64u);
  EXPECT_GE(renderer.compute_intervals()->pair_capacity(), frame.report.pairs);
  const auto c = compare_image(frame.quantity, mesh, camera, 64, 64);
  EXPECT_EQ(c.covered, 64u * 64u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

// More pairs than one radix sort takes are refused before anything is allocated, with the size.
TEST_P(ComputeIntervalsTest, PairsBeyondWhatTheSortTakesAreRefusedWithTheirCount) {
  const TetMesh mesh = make_default_volume();
  frame::FrameRenderer renderer(device(), mesh);
  renderer.render_offscreen(looking_at({2.0, 1.5, 4.5}, glm::dvec3(0.0)), settings_on_backend(), {16, 16});
  volume::ComputeIntervals& intervals = const_cast<volume::ComputeIntervals&>(*renderer.compute_intervals());
  const uint64_t before = intervals.bytes();
  const uint64_t too_many = 65535ull * 1024ull + 1ull;
  try {
    intervals.reserve_pairs(too_many);
    ADD_FAILURE() << "no refusal";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "volume-backend compute");
    EXPECT_NE(std::string(e.what()).find(std::to_string(too_many)), std::string::npos) << e.what();
  }
  EXPECT_EQ(intervals.bytes(), before);
  // Each pair costs its key and value and the sort's scratch for both.
  EXPECT_GE(volume::ComputeIntervals::bytes_for(1000, 16, 2'000'000) - volume::ComputeIntervals::bytes_for(1000, 16, 1'000'000),
            16'000'000u);
}

PRISMOID_ON_COMPUTE_BACKEND(ComputeIntervalsTest);

// 56^3 Kuhn cubes: 1,053,696 cells at 64x64, on both backends. The compute backend holds most
// cells in a tile of their own; the mesh backend needs 65,856 workgroups of 16 cells, more than
// one draw may launch on lavapipe (maxMeshWorkGroupCount 65,536), so it draws in two.
class MillionCellsTest : public test::IntervalShadingTest {};

TEST_P(MillionCellsTest, AMillionCellsAtASmallImageMatchTheReference) {
  const TetMesh mesh = make_box_mesh(glm::dvec3(-1.0), glm::dvec3(1.0), 56, [](const glm::dvec3& p) {
    return 0.8 + 0.6 * std::sin(3.0 * p.x + 1.0) * std::cos(2.0 * p.y - 0.5) + 0.4 * p.z * p.z;
  });
  ASSERT_GT(mesh.tets.size(), 1'000'000u);
  Camera camera = fit_camera(bounds_of(mesh));
  camera.eye = camera.target + glm::dvec3(2.3, 1.7, 4.1);
  const auto c = compare(mesh, camera, 64, 64);
  EXPECT_GT(c.covered, 1500u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
  std::printf("1,053,696 cells at 64x64: max error %.3g, worst pixel at %.2f of its tolerance\n", c.max_error,
              c.max_relative_to_tolerance);
}

PRISMOID_ON_BOTH_BACKENDS(MillionCellsTest);

}  // namespace
}  // namespace prismoid
