// Interval shading against the CPU double-precision reference.
//
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
//     surface, hence sigma * 2 * depth_max * 2^-19 * (ray length per unit depth, <= 1.5
//     at these fields of view) for each cell the ray crosses, plus the rounding of the
//     additive blend, one ulp of the sum per cell added.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/generators.hpp"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

class IntervalShadingTest : public test::GpuTest {
 protected:
  std::vector<float> render(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h) {
    frame::FrameRenderer renderer(device(), mesh);
    frame::FrameSettings settings;
    settings.resolve.quantity = volume::Quantity::OpticalDepth;
    return renderer.render_offscreen(camera, settings, {w, h}).quantity;
  }

  struct Comparison {
    size_t failures = 0;
    size_t covered = 0;
    double max_error = 0.0;
    double max_relative_to_tolerance = 0.0;  // how close the worst pixel came to failing
    std::string first_failure;
  };

  Comparison compare(const TetMesh& mesh, const Camera& camera, uint32_t w, uint32_t h) {
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
    const double per_cell_tol = sigma_max * 2.0 * depth_max * std::ldexp(1.0, -19) * 1.5;

    Comparison c;
    for (size_t i = 0; i < ref.size(); ++i) {
      EXPECT_TRUE(std::isfinite(gpu[i])) << "pixel " << i << " is not finite";
      const double err = std::abs(double(gpu[i]) - ref[i]);
      if (ref[i] > 0.0) ++c.covered;
      c.max_error = std::max(c.max_error, err);
      const double float_tol = (cells_hit[i] + 1) * (per_cell_tol + ref[i] * std::ldexp(1.0, -24));
      if (err > snap_tol[i] + float_tol) {
        if (c.failures++ == 0)
          c.first_failure = "pixel (" + std::to_string(i % w) + "," + std::to_string(i / w) + "): gpu " + std::to_string(gpu[i]) +
                            " reference " + std::to_string(ref[i]) + " tolerance " + std::to_string(snap_tol[i] + float_tol);
      }
      if (ref[i] > 0.0) c.max_relative_to_tolerance = std::max(c.max_relative_to_tolerance, err / (snap_tol[i] + float_tol));
    }
    return c;
  }
};

TetMesh single_tet(const std::array<glm::dvec3, 4>& v, double sigma) {
  TetMesh m;
  m.name = "single tetrahedron";
  m.points.assign(v.begin(), v.end());
  m.tets = {{0, 1, 2, 3}};
  m.cell_extinction = {sigma};
  return m;
}

const std::array<glm::dvec3, 4> kRegular = {glm::dvec3(1, 1, 1), glm::dvec3(1, -1, -1), glm::dvec3(-1, 1, -1), glm::dvec3(-1, -1, 1)};

Camera looking_from(const glm::dvec3& eye, const glm::dvec3& target = glm::dvec3(0.0)) {
  Camera c;
  c.eye = eye;
  c.target = target;
  c.up = std::abs(glm::normalize(eye - target).y) > 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  c.fovy_degrees = 50.0;
  c.near_distance = 0.05;
  return c;
}

TEST_F(IntervalShadingTest, SilhouetteTriangleCaseMatchesReference) {
  // Looking from beyond a vertex towards the centroid, that vertex projects inside the
  // opposite face: case 1 (three proxy triangles).
  const Camera camera = looking_from(glm::normalize(kRegular[0]) * 6.0);
  const Comparison c = compare(single_tet(kRegular, 1.0), camera, 64, 64);
  EXPECT_GT(c.covered, 300u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_F(IntervalShadingTest, SilhouetteQuadCaseMatchesReference) {
  // Looking along the axis joining the midpoints of two opposite edges: case 2.
  const Camera camera = looking_from(glm::dvec3(0, 0, 6.0) + glm::dvec3(0.3, 0.2, 0));
  const Comparison c = compare(single_tet(kRegular, 2.0), camera, 64, 64);
  EXPECT_GT(c.covered, 400u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_F(IntervalShadingTest, RandomTetrahedraAndViewsMatchReference) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 12; ++trial) {
    std::array<glm::dvec3, 4> v;
    for (auto& p : v) p = glm::dvec3(u(rng), u(rng), u(rng));
    if (std::abs(signed_volume(v[0], v[1], v[2], v[3])) < 0.02) continue;  // slivers have their own tests
    glm::dvec3 dir = glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
    const Camera camera = looking_from(dir * 5.0);
    const Comparison c = compare(single_tet(v, 1.5), camera, 48, 48);
    EXPECT_EQ(c.failures, 0u) << "trial " << trial << ": " << c.first_failure;
  }
}

TEST_F(IntervalShadingTest, EdgeOnFaceGivesFiniteExactDepth) {
  // The eye lies in the plane of face (1, 2, 3): that face projects to a segment (zero
  // area). The classification must not divide by it, and the image must stay exact.
  const glm::dvec3 centroid = (kRegular[1] + kRegular[2] + kRegular[3]) / 3.0;
  const glm::dvec3 in_plane = centroid + 5.0 * glm::normalize(kRegular[1] - centroid);
  const Camera camera = looking_from(in_plane, glm::dvec3(0.0));
  const Comparison c = compare(single_tet(kRegular, 1.0), camera, 64, 64);
  EXPECT_GT(c.covered, 100u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_F(IntervalShadingTest, DefaultDatasetMatchesReference) {
  const TetMesh mesh = make_default_volume();
  Camera camera = fit_camera(bounds_of(mesh));
  camera.eye = camera.target + glm::dvec3(2.0, 1.5, 4.5);
  const Comparison c = compare(mesh, camera, 64, 48);
  EXPECT_GT(c.covered, 1000u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
  RecordProperty("max_error", std::to_string(c.max_error));
  RecordProperty("worst_error_over_tolerance", std::to_string(c.max_relative_to_tolerance));
  std::printf("default dataset: max |gpu - reference| = %.3g, worst pixel at %.2f of its tolerance\n", c.max_error,
              c.max_relative_to_tolerance);
}

// The near plane cuts the tetrahedron with 1, 2 or 3 vertices behind it: the part in front is
// a prism (3 pieces), a wedge (3 pieces) or a small tetrahedron, and must integrate exactly
// from the near plane on, as the reference does.
TEST_F(IntervalShadingTest, NearPlaneClipCasesMatchReference) {
  const glm::dvec3 v0 = glm::normalize(kRegular[0]);
  struct Case { const char* name; glm::dvec3 eye; double near_distance; };
  const Case cases[] = {
      {"one vertex behind", v0 * 6.0, 5.0},          // v0 at depth 4.27, the others at 6.58
      {"two vertices behind", {0.0, 0.0, 3.0}, 3.0},  // depths 2, 4, 4, 2
      {"three vertices behind", -v0 * 6.0, 6.0},      // v0 at depth 7.73, the others at 5.42
  };
  for (const auto& k : cases) {
    Camera camera = looking_from(k.eye);
    camera.near_distance = k.near_distance;
    camera.fovy_degrees = 60.0;
    const Comparison c = compare(single_tet(kRegular, 1.0), camera, 48, 48);
    EXPECT_GT(c.covered, 50u) << k.name;
    EXPECT_EQ(c.failures, 0u) << k.name << ": " << c.first_failure;
  }
}

TEST_F(IntervalShadingTest, CameraInsideTheMeshMatchesReference) {
  // The eye sits inside a cell of the default dataset: every pixel integrates from the near
  // plane to the far side of the mesh.
  const TetMesh mesh = make_default_volume();
  Camera camera;
  camera.eye = {0.13, 0.07, 0.21};
  camera.target = {1.0, 0.5, -2.0};
  camera.fovy_degrees = 70.0;
  camera.near_distance = 0.01;
  const Comparison c = compare(mesh, camera, 48, 36);
  EXPECT_EQ(c.covered, 48u * 36u);  // inside the volume, every ray sees medium
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
}

TEST_F(IntervalShadingTest, EmptyMeshRendersZero) {
  TetMesh mesh;
  mesh.name = "empty";
  const std::vector<float> gpu = render(mesh, looking_from({0, 0, 5}), 16, 16);
  for (float v : gpu) EXPECT_EQ(v, 0.0f);
}

}  // namespace
}  // namespace prismoid
