#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <string>
#include <limits>
#include <random>

#include "renderer/reference/tet_ray.hpp"
#include "renderer/volume/orientation.hpp"
#include "renderer/volume/visibility_order.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::volume {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TetMesh unit_box(uint32_t n) {
  TetMesh m = make_box_mesh(glm::dvec3(0.0), glm::dvec3(1.0), n, [](const glm::dvec3&) { return 1.0; });
  m.name = "box";
  return m;
}

std::array<glm::dvec3, 4> corners(const TetMesh& m, size_t c) {
  const auto& t = m.tets[c];
  return {m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]};
}

std::array<uint32_t, 3> sorted_face(const TetMesh& m, size_t c, int i) {
  std::array<uint32_t, 3> f;
  for (int k = 0; k < 3; ++k) f[k] = m.tets[c][kFaceVertices[i][k]];
  std::sort(f.begin(), f.end());
  return f;
}

// Drops the six cells of cube (i, j, k) of a box made by make_box_mesh with n cubes a side.
TetMesh without_cube(TetMesh m, uint32_t n, uint32_t i, uint32_t j, uint32_t k) {
  const size_t first = 6 * ((size_t(k) * n + j) * n + i);
  m.tets.erase(m.tets.begin() + long(first), m.tets.begin() + long(first + 6));
  m.cell_extinction.resize(m.tets.size());
  return m;
}

bool is_permutation_of_cells(const std::vector<uint32_t>& order, size_t cells) {
  if (order.size() != cells) return false;
  std::vector<bool> seen(cells, false);
  for (uint32_t c : order) {
    if (c >= cells || seen[c]) return false;
    seen[c] = true;
  }
  return true;
}

// ----- adjacency ----------------------------------------------------------------------------

TEST(TetAdjacency, BoxFacesMatchBothWaysAndBoundaryIsTheBoxSurface) {
  for (uint32_t n = 1; n <= 4; ++n) {
    const TetMesh m = unit_box(n);
    const TetAdjacency adj = build_adjacency(m);
    ASSERT_EQ(adj.neighbour.size(), m.tets.size());
    size_t boundary = 0;
    for (size_t c = 0; c < m.tets.size(); ++c)
      for (int i = 0; i < 4; ++i) {
        const int32_t d = adj.neighbour[c][i];
        const auto face = sorted_face(m, c, i);
        if (d < 0) {
          ++boundary;
          // A boundary face lies in one of the box's six planes: its points share a coordinate
          // equal to 0 or 1.
          bool on_surface = false;
          for (int axis = 0; axis < 3; ++axis)
            for (double side : {0.0, 1.0})
              on_surface = on_surface || std::all_of(face.begin(), face.end(), [&](uint32_t p) { return m.points[p][axis] == side; });
          EXPECT_TRUE(on_surface) << "n " << n << " cell " << c << " face " << i;
          continue;
        }
        ASSERT_NE(d, int32_t(c));
        int back = -1;
        for (int j = 0; j < 4; ++j)
          if (adj.neighbour[size_t(d)][j] == int32_t(c)) back = j;
        ASSERT_GE(back, 0) << "n " << n << ": cell " << d << " does not name cell " << c << " back";
        EXPECT_EQ(sorted_face(m, size_t(d), back), face);
      }
    // Kuhn split: each of the 6 n^2 unit squares on the surface is one face of one cube, and a
    // cube's square faces are each cut into 2 triangles by one diagonal: 12 n^2 triangles.
    EXPECT_EQ(boundary, 12u * n * n);
    EXPECT_EQ(adj.boundary_faces, 12u * n * n);
    EXPECT_TRUE(adj.convex_boundary) << "n " << n;
  }
}

TEST(TetAdjacency, NotchedBoxIsNotConvex) {
  const TetMesh m = without_cube(unit_box(2), 2, 1, 1, 1);
  const TetAdjacency adj = build_adjacency(m);
  // The corner cube took 3 outer squares with it and exposed 3 inner ones: still 12 n^2.
  EXPECT_EQ(adj.boundary_faces, 48u);
  EXPECT_FALSE(adj.convex_boundary);
}

TEST(TetAdjacency, BoxWithACavityIsNotConvex) {
  const TetMesh m = without_cube(unit_box(3), 3, 1, 1, 1);
  const TetAdjacency adj = build_adjacency(m);
  EXPECT_EQ(adj.boundary_faces, 12u * 9 + 12u);  // the outer surface plus the cavity's 6 squares
  EXPECT_FALSE(adj.convex_boundary);
}

TEST(TetAdjacency, TwoSeparateBoxesAreNotConvex) {
  TetMesh m = unit_box(2);
  const TetMesh other = unit_box(2);
  const auto offset = uint32_t(m.points.size());
  for (const auto& p : other.points) m.points.push_back(p + glm::dvec3(3.0, 0.0, 0.0));
  for (auto t : other.tets) {
    for (auto& v : t) v += offset;
    m.tets.push_back(t);
  }
  m.cell_extinction.resize(m.tets.size(), 1.0);
  const TetAdjacency adj = build_adjacency(m);
  EXPECT_EQ(adj.boundary_faces, 2u * 48u);
  EXPECT_FALSE(adj.convex_boundary);  // each piece is convex, their union is not
}

TEST(TetAdjacency, RotatedBoxStaysConvexDespiteRounding) {
  TetMesh m = unit_box(4);
  // A rotation about a generic axis: the coplanar boundary points no longer lie exactly in one
  // plane after rounding, by about 1e-16, far inside the 1e-6 tolerance.
  const glm::dvec3 axis = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const double angle = 0.7, cs = std::cos(angle), sn = std::sin(angle);
  for (auto& p : m.points) p = p * cs + glm::cross(axis, p) * sn + axis * glm::dot(axis, p) * (1.0 - cs) + glm::dvec3(1e3);
  EXPECT_TRUE(build_adjacency(m).convex_boundary);
}

TEST(TetAdjacency, DentBeyondTheToleranceIsNotConvexAndBelowItIsFlat) {
  const TetMesh box = unit_box(2);
  // The centre point of the top face, (0.5, 0.5, 1), is index (2 * 3 + 1) * 3 + 1 = 22.
  ASSERT_EQ(box.points[22], glm::dvec3(0.5, 0.5, 1.0));
  const double diagonal = std::sqrt(3.0);
  TetMesh dented = box;
  dented.points[22].z -= 1e-3;  // a dent of 1e-3 / sqrt(3) of the diagonal: above 1e-6
  EXPECT_FALSE(build_adjacency(dented).convex_boundary);
  TetMesh bumped = box;
  bumped.points[22].z += 1e-3;  // a bump is concave at the bump's base
  EXPECT_FALSE(build_adjacency(bumped).convex_boundary);
  TetMesh shallow = box;
  shallow.points[22].z -= 0.1e-6 * diagonal;  // a tenth of the tolerance: flat
  EXPECT_TRUE(build_adjacency(shallow).convex_boundary);
}

TEST(TetAdjacency, FaceSharedByThreeCellsThrowsNamingItsPoints) {
  TetMesh m;
  m.name = "fan.vtu";
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, 1}, {0.2, 0.2, -1}, {0.3, 0.3, 2}};
  m.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  m.cell_extinction = {1, 1, 1};
  try {
    build_adjacency(m);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.source(), "fan.vtu");
    EXPECT_NE(what.find("points 0 (0, 0, 0) 1 (1, 0, 0) 2 (0, 1, 0)"), std::string::npos) << what;
    EXPECT_NE(what.find("shared by 3 cells (0, 1, 2)"), std::string::npos) << what;
  }
}

TEST(TetAdjacency, CellRepeatingAPointThrows) {
  TetMesh m;
  m.name = "bad.vtu";
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.tets = {{0, 1, 2, 1}};
  m.cell_extinction = {1};
  EXPECT_THROW(build_adjacency(m), InputError);
}

// ----- order along rays ---------------------------------------------------------------------

// Every ray from the eye must meet the cells it crosses in the order's sequence. Crossings
// shorter than kMinLength are left out: ray_tetrahedron's parameters carry rounding of order
// 1e-16 times the distances here (< 10), so a "crossing" that short can be a ray grazing an
// edge, which touches cells the exact ray misses; 1e-9 is far above that and far below any cell
// size in these meshes (>= 1/8 side, so genuine chords shorter than it are rare and only shorten the check).
constexpr double kMinLength = 1e-9;

// Returns how many crossings were checked.
size_t expect_rays_cross_in_order(const TetMesh& m, const VisibilityOrder& order, const glm::dvec3& eye,
                                  std::mt19937& rng, int rays, const char* what) {
  std::vector<uint32_t> position(m.tets.size());
  for (size_t k = 0; k < order.front_to_back.size(); ++k) position[order.front_to_back[k]] = uint32_t(k);
  const Bounds b = bounds_of(m);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  size_t checked = 0;
  for (int r = 0; r < rays; ++r) {
    const glm::dvec3 target = b.min + glm::dvec3(u(rng), u(rng), u(rng)) * (b.max - b.min);
    const glm::dvec3 dir = glm::normalize(target - eye);
    std::vector<std::pair<double, uint32_t>> crossed;  // entry parameter, cell
    for (size_t c = 0; c < m.tets.size(); ++c) {
      const auto in = reference::ray_tetrahedron(corners(m, c), eye, dir, 0.0, kInf);
      if (in.length() > kMinLength) crossed.emplace_back(in.enter, uint32_t(c));
    }
    std::sort(crossed.begin(), crossed.end());
    for (size_t k = 1; k < crossed.size(); ++k) {
      ++checked;
      if (position[crossed[k - 1].second] >= position[crossed[k].second]) {
        ADD_FAILURE() << what << ": eye (" << eye.x << ", " << eye.y << ", " << eye.z << "), ray " << r << ": cell "
                      << crossed[k - 1].second << " at t " << crossed[k - 1].first << " comes at position "
                      << position[crossed[k - 1].second] << " but cell " << crossed[k].second << " at t "
                      << crossed[k].first << " at position " << position[crossed[k].second];
        return checked;
      }
    }
  }
  return checked;
}

glm::dvec3 random_eye_outside(std::mt19937& rng, const Bounds& b) {
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> distance(1.1, 4.0);
  const glm::dvec3 dir = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
  return b.center() + dir * b.radius() * distance(rng);  // beyond the circumscribed sphere
}

glm::dvec3 random_eye_inside(std::mt19937& rng, const Bounds& b) {
  std::uniform_real_distribution<double> u(0.02, 0.98);
  return b.min + glm::dvec3(u(rng), u(rng), u(rng)) * (b.max - b.min);
}

void expect_exact_order_along_rays(const TetMesh& m, uint32_t seed, int eyes_each_side, int rays) {
  const TetAdjacency adj = build_adjacency(m);
  ASSERT_TRUE(adj.convex_boundary);
  std::mt19937 rng(seed);
  const Bounds b = bounds_of(m);
  size_t checked = 0;
  for (int e = 0; e < 2 * eyes_each_side; ++e) {
    const bool inside = e % 2 == 1;
    const glm::dvec3 eye = inside ? random_eye_inside(rng, b) : random_eye_outside(rng, b);
    const VisibilityOrder order = exact_order(m, adj, eye);
    ASSERT_TRUE(is_permutation_of_cells(order.front_to_back, m.tets.size()));
    EXPECT_TRUE(order.acyclic);
    EXPECT_EQ(order.cells_in_cycles, 0u);
    EXPECT_TRUE(order.exact);
    checked += expect_rays_cross_in_order(m, order, eye, rng, rays, inside ? "inside" : "outside");
  }
  // Rays aimed into the mesh cross several cells each; the check must not pass for want of them.
  EXPECT_GT(checked, size_t(2 * eyes_each_side * rays));
}

TEST(ExactOrder, BoxCellsAppearInRayOrderFromEyesOutsideAndInside) {
  for (uint32_t n = 3; n <= 6; ++n) {
    SCOPED_TRACE("n = " + std::to_string(n));
    expect_exact_order_along_rays(unit_box(n), 100 + n, 10, 60);
  }
}

TEST(ExactOrder, EyeInGridPlanesAndOnAMeshPoint) {
  // Eyes whose coordinates lie exactly in planes of many faces: those faces give no constraint
  // (orientation exactly 0), the rest must still order every ray.
  const TetMesh m = unit_box(4);
  const TetAdjacency adj = build_adjacency(m);
  std::mt19937 rng(5);
  for (const glm::dvec3 eye : {glm::dvec3(0.5, 0.5, 3.0), glm::dvec3(0.25, -2.0, 0.75), glm::dvec3(0.5, 0.5, 0.5),
                               glm::dvec3(0.25, 0.75, 0.6), glm::dvec3(1.0, 1.0, 1.0), glm::dvec3(2.0, 2.0, 2.0)}) {
    const VisibilityOrder order = exact_order(m, adj, eye);
    ASSERT_TRUE(is_permutation_of_cells(order.front_to_back, m.tets.size()));
    EXPECT_TRUE(order.exact);
    expect_rays_cross_in_order(m, order, eye, rng, 200, "grid-plane eye");
  }
}

TEST(ExactOrder, JitteredBoxCellsAppearInRayOrder) {
  const uint32_t n = 5;
  TetMesh m = unit_box(n);
  std::mt19937 rng(3);
  // Interior points move by up to 0.12 of a cube side per axis; the boundary stays the box, so
  // the mesh stays convex. The Kuhn cells' smallest altitude is 1/sqrt(2) of a side, so this
  // keeps them positively oriented (asserted below, not assumed).
  std::uniform_real_distribution<double> jitter(-0.12 / n, 0.12 / n);
  for (auto& p : m.points) {
    const bool interior = p.x > 0 && p.x < 1 && p.y > 0 && p.y < 1 && p.z > 0 && p.z < 1;
    if (interior) p += glm::dvec3(jitter(rng), jitter(rng), jitter(rng));
  }
  for (size_t c = 0; c < m.tets.size(); ++c) {
    const auto v = corners(m, c);
    ASSERT_EQ(orient3d_sign(v[0], v[1], v[2], v[3]), 1) << "cell " << c;
  }
  expect_exact_order_along_rays(m, 41, 10, 60);
}

TEST(ExactOrder, NonConvexMeshIsOrderedButNotExact) {
  const TetMesh m = without_cube(unit_box(3), 3, 2, 2, 1);
  const TetAdjacency adj = build_adjacency(m);
  const VisibilityOrder order = exact_order(m, adj, glm::dvec3(2.5, 2.2, 0.9));
  EXPECT_TRUE(is_permutation_of_cells(order.front_to_back, m.tets.size()));
  EXPECT_TRUE(order.acyclic);  // a Kuhn-split box is Delaunay: no cycles through faces
  EXPECT_FALSE(order.exact);
}

// ----- cycles -------------------------------------------------------------------------------

// Three long thin tetrahedra along the sides of a triangle in the xy-plane, each rising from
// z = -0.5 at one corner to z = +0.5 at the next, so seen from above stick k lies over stick
// k + 1 where they cross: a cyclic 'in front of' relation no order can satisfy. A tetrahedron
// spanned by two skew edges (across the stick's ends) has a parallelogram cross-section, so the
// sticks have volume all along.
TetMesh interlocking_sticks(double z_offset) {
  TetMesh m;
  m.name = "sticks";
  const double pi = std::acos(-1.0);
  glm::dvec3 corner[3];
  for (int k = 0; k < 3; ++k) corner[k] = glm::dvec3(std::cos(2 * pi * k / 3), std::sin(2 * pi * k / 3), 0.0);
  for (int k = 0; k < 3; ++k) {
    glm::dvec3 from = corner[k], to = corner[(k + 1) % 3];
    from.z = -0.5, to.z = 0.5;
    const glm::dvec3 start = from - 0.2 * (to - from), end = to + 0.2 * (to - from);
    const glm::dvec3 across = glm::normalize(glm::cross(to - from, glm::dvec3(0, 0, 1))) * 0.1;
    const auto base = uint32_t(m.points.size());
    const glm::dvec3 lift(0.0, 0.0, z_offset), up(0.0, 0.0, 0.1);
    m.points.insert(m.points.end(), {start + across + lift, start - across + lift, end + up + lift, end - up + lift});
    m.tets.push_back({base, base + 1, base + 2, base + 3});
  }
  m.cell_extinction.assign(m.tets.size(), 1.0);
  return m;
}

// Faces of cell c (not yet linked) with the eye strictly on the cell's side (back faces) or not.
int free_face(const TetMesh& m, const TetAdjacency& adj, size_t c, const glm::dvec3& eye, bool back) {
  const auto v = corners(m, c);
  const int side = orient3d_sign(v[0], v[1], v[2], v[3]);
  for (int i = 0; i < 4; ++i) {
    if (adj.neighbour[c][i] >= 0) continue;
    const int* f = kFaceVertices[i];
    const bool eye_on_cell_side = orient3d_sign(v[f[0]], v[f[1]], v[f[2]], eye) == -side;
    if (eye_on_cell_side == back) return i;
  }
  return -1;
}

// The sticks share no faces, so the adjacency is made by hand: "from" names "to" across one of
// its back faces (so from precedes to), and "to" names "from" across a front face when it has
// one free (a face that adds no constraint), as a mesh's symmetric adjacency would.
void link(const TetMesh& m, TetAdjacency& adj, uint32_t from, uint32_t to, const glm::dvec3& eye) {
  const int i = free_face(m, adj, from, eye, true);
  ASSERT_GE(i, 0) << "cell " << from << " has no free back face";
  adj.neighbour[from][i] = int32_t(to);
  const int j = free_face(m, adj, to, eye, false);
  if (j >= 0) adj.neighbour[to][j] = int32_t(from);
}

TEST(ExactOrder, SticksOverlapCyclicallyAlongRays) {
  // The geometry really is cyclic: the vertical ray over each crossing meets stick k first.
  const TetMesh m = interlocking_sticks(0.0);
  const double pi = std::acos(-1.0);
  for (int k = 0; k < 3; ++k) {
    const glm::dvec3 crossing(std::cos(2 * pi * (k + 1) / 3), std::sin(2 * pi * (k + 1) / 3), 10.0);
    const auto near = reference::ray_tetrahedron(corners(m, size_t(k)), crossing, {0, 0, -1}, 0.0, kInf);
    const auto far = reference::ray_tetrahedron(corners(m, size_t((k + 1) % 3)), crossing, {0, 0, -1}, 0.0, kInf);
    ASSERT_GT(near.length(), 0.0) << k;
    ASSERT_GT(far.length(), 0.0) << k;
    EXPECT_LT(near.exit, far.enter) << k;
  }
}

TEST(ExactOrder, CycleIsReportedAndPlacedAsABlock) {
  TetMesh m = interlocking_sticks(0.0);
  // A cell above everything (D) and one below (E), linked in front of and behind the cycle.
  const auto d = uint32_t(m.tets.size());
  m.points.insert(m.points.end(), {{0, 0, 3}, {0.2, 0, 3}, {0, 0.2, 3}, {0, 0, 3.2}, {0, 0, -3}, {0.2, 0, -3}, {0, 0.2, -3}, {0, 0, -2.8}});
  m.tets.push_back({12, 13, 14, 15});
  m.tets.push_back({16, 17, 18, 19});
  m.cell_extinction.assign(m.tets.size(), 1.0);
  const uint32_t e = d + 1;
  const glm::dvec3 eye(0.1, 0.05, 10.0);
  TetAdjacency adj;
  adj.neighbour.assign(m.tets.size(), {-1, -1, -1, -1});
  link(m, adj, 0, 1, eye);
  link(m, adj, 1, 2, eye);
  link(m, adj, 2, 0, eye);
  link(m, adj, d, 0, eye);
  uint32_t last_of_cycle = 0;
  while (free_face(m, adj, last_of_cycle, eye, true) < 0) ++last_of_cycle;
  link(m, adj, last_of_cycle, e, eye);

  const VisibilityOrder order = exact_order(m, adj, eye);
  ASSERT_TRUE(is_permutation_of_cells(order.front_to_back, m.tets.size()));
  EXPECT_FALSE(order.acyclic);
  EXPECT_FALSE(order.exact);
  EXPECT_EQ(order.cells_in_cycles, 3u);
  EXPECT_EQ(order.front_to_back.front(), d);  // what leads into the cycle comes before it
  EXPECT_EQ(order.front_to_back.back(), e);   // what it leads to comes after it
}

TEST(ExactOrder, TwoSeparateCyclesAreBothPlaced) {
  TetMesh m = interlocking_sticks(0.0);
  const TetMesh lower = interlocking_sticks(-3.0);
  for (auto t : lower.tets) {
    for (auto& v : t) v += uint32_t(m.points.size());
    m.tets.push_back(t);
  }
  m.points.insert(m.points.end(), lower.points.begin(), lower.points.end());
  m.cell_extinction.assign(m.tets.size(), 1.0);
  const glm::dvec3 eye(-0.2, 0.1, 8.0);
  TetAdjacency adj;
  adj.neighbour.assign(m.tets.size(), {-1, -1, -1, -1});
  for (uint32_t base : {0u, 3u}) {
    link(m, adj, base, base + 1, eye);
    link(m, adj, base + 1, base + 2, eye);
    link(m, adj, base + 2, base, eye);
  }
  const VisibilityOrder order = exact_order(m, adj, eye);
  ASSERT_TRUE(is_permutation_of_cells(order.front_to_back, m.tets.size()));
  EXPECT_FALSE(order.acyclic);
  EXPECT_EQ(order.cells_in_cycles, 6u);
  // Unconstrained between them, the sets go nearest first: the upper sticks, then the lower.
  for (size_t k = 0; k < 3; ++k) EXPECT_LT(order.front_to_back[k], 3u);
}

// ----- timing -------------------------------------------------------------------------------

TEST(ExactOrder, TimingOnAMillionCells) {
  // Wall time and this process's CPU time: on a shared machine the second shows what the code
  // costs when it is not waiting for a core.
  struct Stopwatch {
    std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
    std::clock_t cpu = std::clock();
    std::string elapsed() const {
      const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
      const double c = double(std::clock() - cpu) / CLOCKS_PER_SEC;
      char text[64];
      std::snprintf(text, sizeof text, "%.3f s wall, %.3f s CPU", w, c);
      return text;
    }
  };
  const TetMesh m = unit_box(55);  // 6 * 55^3 = 998,250 cells
  const Stopwatch build;
  const TetAdjacency adj = build_adjacency(m);
  std::printf("[ timing ] %zu cells, %zu points: build_adjacency %s (%zu boundary faces, convex %d)\n", m.tets.size(),
              m.points.size(), build.elapsed().c_str(), adj.boundary_faces, int(adj.convex_boundary));
  for (const glm::dvec3 eye : {glm::dvec3(2.3, 1.7, 3.1), glm::dvec3(0.31, 0.62, 0.47), glm::dvec3(0.5, 0.5, -4.0)}) {
    const Stopwatch sort;
    const VisibilityOrder order = exact_order(m, adj, eye);
    std::printf("[ timing ] exact_order from (%.2f, %.2f, %.2f): %s\n", eye.x, eye.y, eye.z, sort.elapsed().c_str());
    EXPECT_TRUE(is_permutation_of_cells(order.front_to_back, m.tets.size()));
    EXPECT_TRUE(order.exact);
  }
}

}  // namespace
}  // namespace prismoid::volume
