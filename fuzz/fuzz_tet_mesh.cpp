// TetMesh validation and the quality report, on meshes a hostile file could describe: NaN and
// infinite coordinates, huge and tiny ones, indices out of range, flat and inverted cells, arrays
// of the wrong length. Validation must reject what the renderer cannot use; what it accepts must
// be usable (every index in range, every value finite).
#include <cmath>
#include <limits>

#include <fuzzer/FuzzedDataProvider.h>

#include "fuzz/fuzz_input.hpp"
#include "scene/tet_mesh.hpp"
#include "scene/tet_quality.hpp"

using namespace prismoid;

namespace {

// Small integers make coinciding and flat cells likely; the special values are what files hold
// when they go wrong.
double coordinate(FuzzedDataProvider& in) {
  constexpr double kSpecial[] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity(), 1e300, -1e300, 1e-300,
                                 std::numeric_limits<double>::denorm_min(), -0.0};
  if (in.ConsumeBool()) return in.PickValueInArray(kSpecial);
  return double(in.ConsumeIntegralInRange<int>(-4, 4));
}

std::vector<double> values(FuzzedDataProvider& in, size_t wanted) {
  std::vector<double> v;
  const size_t n = in.ConsumeBool() ? wanted : in.ConsumeIntegralInRange<size_t>(0, wanted + 1);
  for (size_t i = 0; i < n; ++i) v.push_back(coordinate(in));
  return v;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  TetMesh mesh;
  mesh.name = "fuzz";
  const size_t points = in.ConsumeIntegralInRange<size_t>(0, 12);
  const size_t cells = in.ConsumeIntegralInRange<size_t>(0, 12);
  for (size_t i = 0; i < points; ++i) {
    const double x = coordinate(in), y = coordinate(in), z = coordinate(in);
    mesh.points.emplace_back(x, y, z);
  }
  for (size_t c = 0; c < cells; ++c) {
    std::array<uint32_t, 4> tet{};
    for (uint32_t& v : tet) v = in.ConsumeBool() ? in.ConsumeIntegral<uint32_t>() : in.ConsumeIntegralInRange<uint32_t>(0, 13);
    mesh.tets.push_back(tet);
  }
  mesh.cell_extinction = values(in, cells);
  if (in.ConsumeBool()) mesh.point_extinction = values(in, points);
  if (in.ConsumeBool()) mesh.point_scalars = values(in, points);
  if (in.ConsumeBool()) mesh.cell_scalars = values(in, cells);

  fuzz::expect_input_errors_only([&] {
    validate(mesh);
    for (const auto& tet : mesh.tets)
      for (uint32_t v : tet) fuzz::require(v < mesh.points.size(), "a valid mesh's indices are in range");
    for (const auto& p : mesh.points)
      fuzz::require(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), "a valid mesh's points are finite");
    const TetQuality q = tet_quality(mesh);
    fuzz::require(q.zero_volume + q.inverted <= mesh.tets.size(), "quality counts at most every cell once");
    const Bounds b = bounds_of(mesh);
    fuzz::require(b.min.x <= b.max.x && b.min.y <= b.max.y && b.min.z <= b.max.z, "bounds are ordered");
  });
  return 0;
}
