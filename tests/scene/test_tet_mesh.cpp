#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include <algorithm>

#include <glm/geometric.hpp>

#include "scene/coarse_proxy.hpp"
#include "scene/generators.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid {
namespace {

TetMesh one_tet() {
  TetMesh m;
  m.name = "one.vtu";
  m.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.tets = {{0, 1, 2, 3}};
  m.cell_extinction = {1.0};
  return m;
}

void expect_input_error(const TetMesh& m, const std::string& fragment) {
  try {
    validate(m);
    FAIL() << "expected an InputError mentioning '" << fragment << "'";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "one.vtu");
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(TetMeshValidation, AcceptsAGoodMesh) { EXPECT_NO_THROW(validate(one_tet())); }

TEST(TetMeshValidation, NamesTheFileAndTheProblem) {
  TetMesh m = one_tet();
  m.tets[0][2] = 9;
  expect_input_error(m, "refers to point 9");
  m = one_tet();
  m.points[1].y = std::numeric_limits<double>::quiet_NaN();
  expect_input_error(m, "non-finite");
  m = one_tet();
  m.cell_extinction[0] = -1.0;
  expect_input_error(m, "extinction");
  m = one_tet();
  m.cell_extinction.clear();
  expect_input_error(m, "extinction values");
}

TEST(BoxMesh, TetrahedraFillTheBoxExactlyWithPositiveVolumes) {
  const TetMesh m = make_box_mesh(glm::dvec3(-1, -2, 0), glm::dvec3(3, 2, 1), 3, [](const glm::dvec3&) { return 1.0; });
  EXPECT_EQ(m.tets.size(), 6u * 27u);
  double total = 0.0;
  for (const auto& t : m.tets) {
    const double v = signed_volume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]);
    EXPECT_GT(v, 0.0);
    total += v;
  }
  EXPECT_NEAR(total, 4.0 * 4.0 * 1.0, 1e-12);
  EXPECT_NO_THROW(validate(m));
}

}  // namespace
}  // namespace prismoid

namespace prismoid {
namespace {

// The window's coarse proxy (scene/coarse_proxy.hpp) samples the data's fields at grid points:
// on a dataset that is itself that grid it gives the data back, and outside the data nothing.
TEST(CoarseProxy, SamplesTheFieldsAtItsGridPointsAndLeavesOutsideEmpty) {
  const TetMesh data = make_default_volume();  // a 16^3-cube Kuhn grid, point scalars = density
  const TetMesh same = coarse_proxy(data, 16);
  ASSERT_EQ(same.points.size(), data.points.size());
  EXPECT_EQ(same.tets.size(), data.tets.size());
  for (size_t i = 0; i < data.points.size(); ++i) {
    ASSERT_EQ(same.points[i], data.points[i]);
    EXPECT_NEAR(same.point_scalars[i], data.point_scalars[i], 1e-12 * (1.0 + data.point_scalars[i])) << i;
  }
  EXPECT_NO_THROW(validate(same));

  // A ball of extinction 2 seen through an 8^3 grid over its bounds: points inside carry 2,
  // points outside 0, and only cubes reaching into the ball are kept.
  const TetMesh ball = make_ball_mesh(glm::dvec3(0.0), 1.0, 3, 2.0);
  const TetMesh proxy = coarse_proxy(ball, 8);
  EXPECT_LT(proxy.tets.size(), size_t(6 * 8 * 8 * 8));
  EXPECT_GT(proxy.tets.size(), size_t(6 * 4 * 4 * 4));
  size_t inside = 0;
  for (size_t i = 0; i < proxy.points.size(); ++i) {
    const double r = glm::length(proxy.points[i]);
    if (r < 0.9) {  // well inside the icosphere's faceted surface
      EXPECT_NEAR(proxy.point_extinction[i], 2.0, 1e-12) << i;
      ++inside;
    } else if (r > 1.0 + 1e-9) {
      EXPECT_EQ(proxy.point_extinction[i], 0.0) << i;
    }
  }
  EXPECT_GT(inside, 100u);
  for (const auto& t : proxy.tets) {
    double most = 0.0;
    for (uint32_t k : t) most = std::max(most, proxy.point_extinction[k]);
    EXPECT_GT(most, 0.0);  // every kept cube reaches into the ball
  }
  EXPECT_NO_THROW(validate(proxy));
}

}  // namespace
}  // namespace prismoid
