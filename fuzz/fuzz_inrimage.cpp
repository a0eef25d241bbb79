// INRIMAGE-4 (.inr and .inr.gz: gzread passes plain files through, so both arrive here) through the
// whole image path: header, size guard, voxels, Kuhn split, validation.
#include "fuzz/fuzz_input.hpp"
#include "io/inrimage.hpp"
#include "io/voxel_tets.hpp"
#include "scene/tet_mesh.hpp"

using namespace prismoid;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::ScratchFile scratch(".inr");
  const std::string& path = scratch.write(data, size);
  fuzz::expect_input_errors_only([&] {
    const io::detail::InrHeader header = io::detail::read_inr_header(path);
    for (uint32_t subsample : {1u, 2u}) {
      io::ImageReadOptions options;
      options.subsample = subsample;
      options.max_cells = 1u << 14;  // the guard stops big headers early; small images keep each run fast
      io::detail::check_image_size(path, header.dims, options);
      io::detail::VoxelGrid grid;
      for (int a = 0; a < 3; ++a) grid.dims[a] = io::detail::kept_voxels(header.dims[a], subsample);
      grid.origin = header.origin;
      grid.spacing = header.spacing * double(subsample);
      grid.values = io::detail::read_inr_voxels(path, header, subsample);
      fuzz::require(grid.values.size() == grid.dims[0] * grid.dims[1] * grid.dims[2], "one value per kept voxel");
      const TetMesh mesh = io::detail::voxel_grid_to_tets(grid, path, options);
      validate(mesh);
    }
  });
  return 0;
}
