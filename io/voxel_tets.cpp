#include "io/voxel_tets.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "io/kuhn_split.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::io {

uint64_t image_tet_count(const uint64_t dims[3], uint32_t subsample) {
  uint64_t count = 6;  // saturates rather than wrapping, for headers with absurd sizes
  for (int a = 0; a < 3; ++a)
    if (__builtin_mul_overflow(count, detail::kept_voxels(dims[a], subsample) - 1, &count)) return std::numeric_limits<uint64_t>::max();
  return count;
}

namespace detail {

// The guard runs on the header alone, before the voxels are read.
void check_image_size(const std::string& path, const uint64_t dims[3], const ImageReadOptions& options) {
  const std::string shape = std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]);
  if (options.subsample == 0) throw InputError(path, "subsample must be at least 1");
  for (int a = 0; a < 3; ++a)
    if (kept_voxels(dims[a], options.subsample) < 2)
      throw InputError(path, "the image is " + shape + " voxels" +
                                 (options.subsample > 1 ? " (keeping 1 in " + std::to_string(options.subsample) + " per axis)" : std::string()) +
                                 "; it needs at least 2 voxels along each axis to make cells");
  const uint64_t count = image_tet_count(dims, options.subsample);
  if (count > options.max_cells) {
    // The count falls as the subsample grows, while every axis keeps 2 voxels (up to the shortest
    // axis's length - 1): a binary search finds the smallest subsample that fits.
    std::string advice = "no subsampling fits (2 x 2 x 2 voxels already make 6)";
    uint64_t lo = uint64_t(options.subsample) + 1;
    uint64_t hi = std::min<uint64_t>(std::min({dims[0], dims[1], dims[2]}) - 1, std::numeric_limits<uint32_t>::max());
    if (lo <= hi && image_tet_count(dims, uint32_t(hi)) <= options.max_cells) {
      while (lo < hi) {
        const uint64_t mid = lo + (hi - lo) / 2;
        if (image_tet_count(dims, uint32_t(mid)) <= options.max_cells) hi = mid;
        else lo = mid + 1;
      }
      advice = "--subsample " + std::to_string(hi) + " (1 voxel in " + std::to_string(hi) + " per axis) makes " +
               std::to_string(image_tet_count(dims, uint32_t(hi)));
    }
    throw InputError(path, "the image is " + shape + " voxels, which make " + std::to_string(count) +
                               " tetrahedra, more than the limit of " + std::to_string(options.max_cells) + "; " + advice);
  }
  uint64_t points = 1;
  for (int a = 0; a < 3; ++a)
    if (__builtin_mul_overflow(points, kept_voxels(dims[a], options.subsample), &points)) points = std::numeric_limits<uint64_t>::max();
  if (points > std::numeric_limits<uint32_t>::max())
    throw InputError(path, "the image has more voxels than 32-bit point indices can address; subsample it");
}

TetMesh voxel_grid_to_tets(const VoxelGrid& grid, const std::string& name, const ImageReadOptions& options) {
  const uint64_t nx = grid.dims[0], ny = grid.dims[1], nz = grid.dims[2];
  auto point_index = [nx, ny](uint64_t i, uint64_t j, uint64_t k) { return uint32_t(i + nx * (j + ny * k)); };
  TetMesh mesh;
  mesh.name = name;
  mesh.points.reserve(nx * ny * nz);
  for (uint64_t k = 0; k < nz; ++k) {
    report(options.progress, 0.2 * double(k) / double(nz), "placing voxel points", name);
    for (uint64_t j = 0; j < ny; ++j)
      for (uint64_t i = 0; i < nx; ++i) mesh.points.push_back(grid.origin + glm::dvec3(double(i), double(j), double(k)) * grid.spacing);
  }

  // Every cell is a translate of cell (0,0,0), so its six tetrahedra (io/kuhn_split.hpp), as
  // index offsets from the cell's first corner and oriented positively (spacings may be
  // negative), are worked out once there.
  std::array<uint32_t, 4> offsets[6];
  for (size_t t = 0; t < 6; ++t) {
    for (size_t v = 0; v < 4; ++v) {
      const uint32_t corner = kKuhnTets[t][v];
      offsets[t][v] = point_index(corner & 1u, (corner >> 1) & 1u, (corner >> 2) & 1u);
    }
    const auto& o = offsets[t];
    if (signed_volume(mesh.points[o[0]], mesh.points[o[1]], mesh.points[o[2]], mesh.points[o[3]]) < 0.0) std::swap(offsets[t][2], offsets[t][3]);
  }
  mesh.tets.reserve(6 * (nx - 1) * (ny - 1) * (nz - 1));
  for (uint64_t k = 0; k + 1 < nz; ++k) {
    report(options.progress, 0.2 + 0.8 * double(k) / double(nz - 1), "splitting voxel cells into tetrahedra", name);
    for (uint64_t j = 0; j + 1 < ny; ++j)
      for (uint64_t i = 0; i + 1 < nx; ++i) {
        const uint32_t first = point_index(i, j, k);
        for (const auto& o : offsets) mesh.tets.push_back({first + o[0], first + o[1], first + o[2], first + o[3]});
      }
  }
  report(options.progress, 1.0, "splitting voxel cells into tetrahedra", name);

  mesh.point_scalars = grid.values;
  if (options.role == ArrayRole::Extinction) {
    set_point_extinction(mesh, grid.values, options.density_scale);
  } else {
    mesh.cell_extinction.assign(mesh.tets.size(), options.density_scale);
  }
  return mesh;
}

void set_point_extinction(TetMesh& mesh, const std::vector<double>& values, double density_scale) {
  mesh.point_extinction.resize(values.size());
  for (size_t i = 0; i < values.size(); ++i) mesh.point_extinction[i] = values[i] * density_scale;
  mesh.cell_extinction.clear();
  mesh.cell_extinction.reserve(mesh.tets.size());
  for (const auto& tet : mesh.tets) {
    double sigma = 0.0;
    for (uint32_t v : tet) sigma += 0.25 * mesh.point_extinction[v];
    mesh.cell_extinction.push_back(sigma);
  }
}

}  // namespace detail

}  // namespace prismoid::io
