#pragma once
// What a mesh file holds and what reading it would produce, for `prismoid info`: plain data,
// no VTK types.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "io/vtk_tet_io.hpp"
#include "scene/bounds.hpp"

namespace prismoid::io {

struct ArraySummary {
  std::string name;
  bool per_point = false;  // else per cell
  int components = 1;
  double min = 0.0, max = 0.0;  // of the values, or of the magnitude for vectors
};

struct DatasetInfo {
  size_t points = 0;  // in the file (after merging pieces)
  std::map<std::string, size_t> cells_by_type;
  std::vector<ArraySummary> arrays;
  Bounds bounds;
  MeshConversion conversion;  // what read_tet_mesh produces from it
  size_t mesh_points = 0;     // points of the tetrahedral mesh (all the file's points are kept)
  double volume = 0.0;        // sum of |tetrahedron volume| after conversion
  std::vector<std::string> blocks;  // a .vtm's blocks, one line each ("block 1 'density': vtkImageData (not drawn)")
};

// Reads the file as read_tet_mesh does (same errors) and summarizes it.
DatasetInfo describe_dataset(const std::string& path);

// The renderer's mesh buffers (renderer/volume/interval_shading.cpp, upload()): a float4
// position per point; per tetrahedron four uint32 indices, a float sigma and a float scalar.
// A chosen point array adds a float per point for each role it plays.
constexpr size_t kGpuBytesPerPoint = 16;
constexpr size_t kGpuBytesPerTet = 24;
inline size_t estimated_gpu_bytes(size_t tets, size_t points) { return kGpuBytesPerTet * tets + kGpuBytesPerPoint * points; }

}  // namespace prismoid::io
