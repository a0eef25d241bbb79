// Interval shading against the CPU double-precision reference.
// (Fixture and per-pixel tolerances: interval_comparison.hpp/.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <glm/gtc/matrix_transform.hpp>
#include <functional>
#include <random>
#include <utility>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/reference/tet_ray.hpp"
#include "scene/generators.hpp"
#include "scene/tet_mesh.hpp"
#include "volume/interval_comparison.hpp"

namespace prismoid {
namespace {

using test::IntervalShadingTest;

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

TEST_P(IntervalShadingTest, SilhouetteTriangleCaseMatchesReference) {
  // Looking from beyond a vertex towards the centroid, that vertex projects inside the
  // opposite face: case 1 (three proxy triangles).
  const Camera camera = looking_from(glm::normalize(kRegular[0]) * 6.0);
  const Comparison c = compare(single_tet(kRegular, 1.0), camera, 64, 64);
  EXPECT_GT(c.covered, 300u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_P(IntervalShadingTest, SilhouetteQuadCaseMatchesReference) {
  // Looking along the axis joining the midpoints of two opposite edges: case 2.
  const Camera camera = looking_from(glm::dvec3(0, 0, 6.0) + glm::dvec3(0.3, 0.2, 0));
  const Comparison c = compare(single_tet(kRegular, 2.0), camera, 64, 64);
  EXPECT_GT(c.covered, 400u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_P(IntervalShadingTest, RandomTetrahedraAndViewsMatchReference) {
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

TEST_P(IntervalShadingTest, EdgeOnFaceGivesFiniteExactDepth) {
  // The eye lies in the plane of face (1, 2, 3): that face projects to a segment (zero
  // area). The classification must not divide by it, and the image must stay exact.
  const glm::dvec3 centroid = (kRegular[1] + kRegular[2] + kRegular[3]) / 3.0;
  const glm::dvec3 in_plane = centroid + 5.0 * glm::normalize(kRegular[1] - centroid);
  const Camera camera = looking_from(in_plane, glm::dvec3(0.0));
  const Comparison c = compare(single_tet(kRegular, 1.0), camera, 64, 64);
  EXPECT_GT(c.covered, 100u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_P(IntervalShadingTest, DefaultDatasetMatchesReference) {
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
TEST_P(IntervalShadingTest, NearPlaneClipCasesMatchReference) {
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

TEST_P(IntervalShadingTest, CameraInsideTheMeshMatchesReference) {
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

// Hard cases: far from the origin, tiny cells, slivers, zero-volume cells.

TEST_P(IntervalShadingTest, FarFromOriginMatchesReference) {
  // Unit-sized cells at an offset of 1e5: float positions relative to the mesh centre keep
  // the precision that world coordinates in float (ulp 2^-7 at 1e5) would lose.
  const glm::dvec3 offset(1e5, -2e5, 1.5e5);
  TetMesh mesh = make_box_mesh(offset - 1.0, offset + 1.0, 4, [&](const glm::dvec3& p) {
    return 1.0 + 0.5 * std::sin(p.x - offset.x) * std::cos(p.y - offset.y);
  });
  Camera camera;
  camera.eye = offset + glm::dvec3(2.0, 1.5, 4.5);
  camera.target = offset;
  camera.fovy_degrees = 40.0;
  camera.near_distance = 0.1;
  const Comparison c = compare(mesh, camera, 48, 36);
  EXPECT_GT(c.covered, 300u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_P(IntervalShadingTest, TinyCellsMatchReference) {
  // A mesh 2e-6 across with sigma 1e6, so the optical depth is of order one.
  TetMesh mesh = make_box_mesh(glm::dvec3(-1e-6), glm::dvec3(1e-6), 3, [](const glm::dvec3&) { return 1e6; });
  Camera camera;
  camera.eye = {2e-6, 1.5e-6, 4.5e-6};
  camera.fovy_degrees = 40.0;
  camera.near_distance = 1e-7;
  const Comparison c = compare(mesh, camera, 48, 36);
  EXPECT_GT(c.covered, 300u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

TEST_P(IntervalShadingTest, SliversAndZeroVolumeCellsStayFiniteAndExact) {
  // Needle, cap and wedge slivers (heights 1e-4 of their size) and exactly flat cells
  // (coplanar, and with a repeated vertex): the flat ones contribute nothing.
  TetMesh mesh;
  mesh.name = "slivers";
  auto add = [&](std::array<glm::dvec3, 4> v, double sigma) {
    const auto base = static_cast<uint32_t>(mesh.points.size());
    mesh.points.insert(mesh.points.end(), v.begin(), v.end());
    mesh.tets.push_back({base, base + 1, base + 2, base + 3});
    mesh.cell_extinction.push_back(sigma);
  };
  add({glm::dvec3(-1, -1, 0), glm::dvec3(1, -1, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, 0, 1e-4)}, 50.0);      // cap
  add({glm::dvec3(-1, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1e-4, 1), glm::dvec3(0, -1e-4, -1)}, 50.0);   // wedge
  add({glm::dvec3(0, 0, -1), glm::dvec3(0, 0, 1), glm::dvec3(1e-4, 0, 0), glm::dvec3(0, 1e-4, 0)}, 50.0);     // needle
  add({glm::dvec3(-1, -1, 0.5), glm::dvec3(1, -1, 0.5), glm::dvec3(1, 1, 0.5), glm::dvec3(-1, 1, 0.5)}, 9.0);  // flat
  add({glm::dvec3(-1, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 1)}, 9.0);            // repeated vertex
  for (const glm::dvec3 eye : {glm::dvec3(0.3, 0.2, 5.0), glm::dvec3(4.0, 0.1, 0.2), glm::dvec3(2.0, 3.0, 2.5)}) {
    const Comparison c = compare(mesh, looking_from(eye), 48, 48);
    EXPECT_EQ(c.failures, 0u) << "eye " << eye.x << "," << eye.y << "," << eye.z << ": " << c.first_failure;
  }
}

// The ray parameters where origin + t * direction (t >= 0) enters and leaves the cube
// [-1, 1]^3, by the slab method (t1 <= t0 when it misses).
std::pair<double, double> cube_interval(const glm::dvec3& origin, const glm::dvec3& direction) {
  double t0 = 0.0, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    const double ta = (-1.0 - origin[a]) / direction[a], tb = (1.0 - origin[a]) / direction[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  return {t0, t1};
}

// The ray parameters where a ray enters and leaves a convex body, in closed form.
using Chord = std::function<std::pair<double, double>(const glm::dvec3& origin, const glm::dvec3& direction)>;

// For a field linear over a convex body, the optical depth along a ray is the chord times sigma
// at the chord's midpoint. The reference must match that to rounding, the GPU the reference
// within its per-pixel tolerances. Rays grazing the body are left to the per-pixel tolerances.
void expect_closed_form_chord(IntervalShadingTest& test, const TetMesh& mesh, const Camera& camera, const Chord& chord,
                              const std::function<double(const glm::dvec3&)>& sigma) {
  const uint32_t w = 40, h = 40;
  const std::vector<double> ref = reference::optical_depth_image(mesh, camera, w, h);
  size_t interior = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const glm::dvec3 d = reference::ray_direction(camera, w, h, x + 0.5, y + 0.5);
      const auto [t0, t1] = chord(camera.eye, d);
      if (t1 - t0 < 0.05) continue;
      ++interior;
      const double exact = (t1 - t0) * sigma(camera.eye + 0.5 * (t0 + t1) * d);
      EXPECT_NEAR(ref[y * w + x], exact, 1e-12) << "reference, pixel " << x << "," << y;
    }
  EXPECT_GT(interior, 300u);
  const auto c = test.compare(mesh, camera, w, h);
  EXPECT_EQ(c.failures, 0u) << c.first_failure;
}

void expect_closed_form_through_cube(IntervalShadingTest& test, const TetMesh& mesh,
                                     const std::function<double(const glm::dvec3&)>& sigma) {
  Camera camera;
  camera.eye = {1.7, 2.1, 3.9};
  camera.fovy_degrees = 45.0;
  camera.near_distance = 0.1;
  expect_closed_form_chord(test, mesh, camera, cube_interval, sigma);
}

// For a field sigma that is linear over the cube [-1, 1]^3 (constant included), the optical
// depth along a ray is the chord times sigma at the chord's midpoint, in closed form. The
// tetrahedral reference must match it to rounding (the Kuhn cells partition the cube), and
// the GPU must match the reference within the per-pixel tolerances derived above.
TEST_P(IntervalShadingTest, ConstantCubeEqualsSigmaTimesChordInClosedForm) {
  auto sigma = [](const glm::dvec3&) { return 0.75; };
  expect_closed_form_through_cube(*this, make_box_mesh(glm::dvec3(-1), glm::dvec3(1), 5, sigma), sigma);
}

// A tetrahedralized ball of constant extinction: the optical depth is sigma times the chord
// through the (convex, polyhedral) ball, computed in closed form from the boundary faces'
// planes alone (entry = the last plane entered, exit = the first left), which knows nothing
// of the tetrahedra. The reference must match it to rounding, and the GPU the reference.
TEST_P(IntervalShadingTest, ConstantBallEqualsSigmaTimesChordInClosedForm) {
  const double sigma = 0.8;
  const TetMesh mesh = make_ball_mesh(glm::dvec3(0.2, -0.1, 0.3), 1.0, 2, sigma);
  ASSERT_EQ(mesh.tets.size(), 320u);
  struct Plane { glm::dvec3 n; double d; };  // inside: dot(n, p) <= d
  std::vector<Plane> planes;
  const glm::dvec3 centre = mesh.points.back();
  for (const auto& t : mesh.tets) {
    const glm::dvec3 a = mesh.points[t[1]], b = mesh.points[t[2]], c = mesh.points[t[3]];
    glm::dvec3 n = glm::cross(b - a, c - a);
    if (glm::dot(n, centre - a) > 0.0) n = -n;
    planes.push_back({n, glm::dot(n, a)});
  }
  Camera camera;
  camera.eye = {1.5, 2.0, 3.2};
  camera.target = glm::dvec3(0.2, -0.1, 0.3);
  camera.fovy_degrees = 45.0;
  camera.near_distance = 0.1;
  // Entry = the last boundary plane entered, exit = the first left.
  auto chord = [&](const glm::dvec3& origin, const glm::dvec3& dir) {
    double t0 = 0.0, t1 = 1e300;
    for (const Plane& p : planes) {
      const double rate = glm::dot(p.n, dir), slack = p.d - glm::dot(p.n, origin);
      if (rate > 0.0) t1 = std::min(t1, slack / rate);
      else if (rate < 0.0) t0 = std::max(t0, slack / rate);
    }
    return std::make_pair(t0, t1);
  };
  expect_closed_form_chord(*this, mesh, camera, chord, [&](const glm::dvec3&) { return sigma; });
}

// Beyond the paper: per-vertex extinction, linear in each cell.

TEST_P(IntervalShadingTest, GloballyLinearFieldEqualsClosedForm) {
  // Linear everywhere, so every cell's interpolation reproduces it exactly.
  auto sigma = [](const glm::dvec3& p) { return 1.0 + 0.3 * p.x + 0.2 * p.y - 0.1 * p.z; };
  TetMesh mesh = make_box_mesh(glm::dvec3(-1), glm::dvec3(1), 4, sigma);
  mesh.point_extinction = mesh.point_scalars;
  expect_closed_form_through_cube(*this, mesh, sigma);
}

TEST_P(IntervalShadingTest, PointExtinctionOnDefaultDatasetMatchesReference) {
  TetMesh mesh = make_default_volume();
  mesh.point_extinction = mesh.point_scalars;  // the Gaussian blobs sampled at the points
  Camera camera = fit_camera(bounds_of(mesh));
  camera.eye = camera.target + glm::dvec3(2.0, 1.5, 4.5);
  const Comparison c = compare(mesh, camera, 64, 48);
  EXPECT_GT(c.covered, 1000u);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
}

TEST_P(IntervalShadingTest, LinearFieldWithCameraInsideMatchesReference) {
  TetMesh mesh = make_default_volume();
  mesh.point_extinction = mesh.point_scalars;
  Camera camera;
  camera.eye = {0.13, 0.07, 0.21};
  camera.target = {1.0, 0.5, -2.0};
  camera.fovy_degrees = 70.0;
  camera.near_distance = 0.01;
  const Comparison c = compare(mesh, camera, 32, 24);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
}

TEST_P(IntervalShadingTest, EdgeOnFacesAlongTheViewAxisStayFiniteAndExact) {
  // Regression: the default camera looks down the z axis through the centre of the Kuhn grid,
  // so the eye lies in the planes x = 0, y = 0 and x = ±y, and many faces are exactly edge-on.
  // Their proxies once kept zero-area triangles that the rasterizer still covered along a
  // screen diagonal: NaN at 3 pixels and errors of 0.5 at 1024x1024 (none at 256x256, so this
  // test needs the full size; about a minute on lavapipe).
  TetMesh mesh = make_default_volume();
  mesh.point_extinction = mesh.point_scalars;
  const Comparison c = compare(mesh, fit_camera(bounds_of(mesh)), 1024, 1024);
  EXPECT_EQ(c.failures, 0u) << c.first_failure << " (max error " << c.max_error << ")";
}

TEST_P(IntervalShadingTest, ProxiesFarLargerThanTheViewportStayExact) {
  // Regression: lavapipe mis-interpolated `noperspective` attributes on proxy triangles its
  // clipper cuts, giving errors up to 0.43 (of ~1) when the eye sat inside a big cell or a
  // narrow field of view magnified one; the H100 was exact. The proxies now use ordinary
  // interpolation, which equals screen-space interpolation at w = 1.
  Camera inside = looking_from({0.1, -0.05, 0.2});
  inside.target = {0.3, 0.2, -1.0};
  inside.fovy_degrees = 70.0;
  inside.near_distance = 0.02;
  Camera magnified = looking_from({0.3, 0.2, 6.0}, {0.1, 0.1, 0.0});
  magnified.fovy_degrees = 3.0;
  for (const Camera& camera : {inside, magnified}) {
    const Comparison c = compare(single_tet(kRegular, 1.0), camera, 32, 32);
    EXPECT_EQ(c.covered, 32u * 32u);
    EXPECT_EQ(c.failures, 0u) << "fovy " << camera.fovy_degrees << ": " << c.first_failure;
  }
}

TEST_P(IntervalShadingTest, EmptyMeshRendersZero) {
  TetMesh mesh;
  mesh.name = "empty";
  const std::vector<float> gpu = render(mesh, looking_from({0, 0, 5}), 16, 16);
  for (float v : gpu) EXPECT_EQ(v, 0.0f);
}

PRISMOID_ON_BOTH_BACKENDS(IntervalShadingTest);

}  // namespace
}  // namespace prismoid
