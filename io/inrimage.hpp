#pragma once
// INRIMAGE-4 (.inr, and gzip-compressed .inr.gz), the format of CGAL's demo images: a text header
// "#INRIMAGE-4#{" ... "##}" of KEY=value lines padded with newlines, then raw voxels, x fastest.
// Internal to io/. Strict: anything it does not understand is an InputError naming the file.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace prismoid::io::detail {

struct InrHeader {
  uint64_t dims[3] = {0, 0, 0};  // XDIM, YDIM, ZDIM
  glm::dvec3 spacing{1.0};       // VX, VY, VZ
  glm::dvec3 origin{0.0};        // TX, TY, TZ (CGAL writes them when non-zero)
  enum class Type { Unsigned, Signed, Float } type = Type::Unsigned;
  uint32_t bytes_per_voxel = 1;  // PIXSIZE / 8
  bool big_endian = false;       // from CPU
};

InrHeader read_inr_header(const std::string& path);

// The voxels of every subsample-th row, slice and column, in x-fastest order, as doubles.
// Throws InputError when the file is truncated or has bytes after the voxels.
std::vector<double> read_inr_voxels(const std::string& path, const InrHeader& header, uint32_t subsample);

}  // namespace prismoid::io::detail
