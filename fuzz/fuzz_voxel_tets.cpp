// The Kuhn split of small voxel grids of any shape, spacing and origin: after the size guard,
// the mesh has 6 (nx-1)(ny-1)(nz-1) cells with indices in range, and for an ordinary positive
// spacing every cell is positively oriented and the cells fill the grid's box exactly.
#include <algorithm>
#include <cmath>
#include <limits>

#include <fuzzer/FuzzedDataProvider.h>
#include <glm/common.hpp>

#include "fuzz/fuzz_input.hpp"
#include "io/voxel_tets.hpp"
#include "scene/tet_mesh.hpp"
#include "scene/tet_quality.hpp"

using namespace prismoid;

namespace {

double spacing(FuzzedDataProvider& in) {
  constexpr double kSpecial[] = {0.0, -1.0, 1e-300, 1e300, std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::infinity()};
  if (in.ConsumeBool()) return in.PickValueInArray(kSpecial);
  return in.ConsumeFloatingPointInRange<double>(1e-3, 1e3);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider in(data, size);
  uint64_t full[3];
  for (uint64_t& n : full) n = in.ConsumeIntegralInRange<uint64_t>(1, 9);
  io::ImageReadOptions options;
  options.subsample = in.ConsumeIntegralInRange<uint32_t>(0, 4);
  options.max_cells = in.ConsumeIntegralInRange<uint64_t>(0, 3000);
  options.role = in.ConsumeBool() ? io::ArrayRole::Extinction : io::ArrayRole::Scalars;
  options.density_scale = in.ConsumeFloatingPointInRange<double>(0.0, 10.0);
  io::detail::VoxelGrid grid;
  for (int a = 0; a < 3; ++a) {
    grid.spacing[a] = spacing(in);
    grid.origin[a] = in.ConsumeFloatingPointInRange<double>(-1e3, 1e3);
  }
  fuzz::expect_input_errors_only([&] {
    io::detail::check_image_size("fuzz", full, options);
    for (int a = 0; a < 3; ++a) grid.dims[a] = io::detail::kept_voxels(full[a], options.subsample);
    const size_t voxels = grid.dims[0] * grid.dims[1] * grid.dims[2];
    for (size_t i = 0; i < voxels; ++i) grid.values.push_back(double(in.ConsumeIntegralInRange<int>(0, 255)));
    const TetMesh mesh = io::detail::voxel_grid_to_tets(grid, "fuzz", options);
    const uint64_t cells = io::image_tet_count(full, options.subsample);
    fuzz::require(mesh.tets.size() == cells && cells <= options.max_cells, "6 cells per voxel cell, within the guard");
    validate(mesh);
    bool ordinary = true;
    for (int a = 0; a < 3; ++a) ordinary = ordinary && grid.spacing[a] >= 1e-3 && grid.spacing[a] <= 1e3;
    if (!ordinary) return;
    const TetQuality q = tet_quality(mesh);
    fuzz::require(q.inverted == 0 && q.zero_volume == 0, "every cell positively oriented");
    // The cells tile the box: their volumes sum to its volume up to rounding. Each point
    // coordinate origin + i h is off by at most eps M (M the largest coordinate), so an edge of
    // length h by a relative 2 eps M / h; a triple product of three such edges by 3 times that
    // plus its own 64 eps (is_flat's bound); summing n positive volumes adds n eps at most.
    const glm::dvec3 box = glm::dvec3(grid.dims[0] - 1, grid.dims[1] - 1, grid.dims[2] - 1) * grid.spacing;
    const double volume = box.x * box.y * box.z;
    const glm::dvec3 far = glm::abs(grid.origin) + glm::abs(box);
    const double largest = std::max({far.x, far.y, far.z});
    const double finest = std::min({grid.spacing.x, grid.spacing.y, grid.spacing.z});
    const double eps = std::numeric_limits<double>::epsilon();
    fuzz::require(std::abs(q.total_volume - volume) <= (64.0 + 6.0 * largest / finest + double(mesh.tets.size())) * eps * volume, "the cells fill the box");
  });
  return 0;
}
