#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scene/generators.hpp"
#include "scene/input_error.hpp"

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
