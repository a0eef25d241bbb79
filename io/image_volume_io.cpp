#include "io/image_volume_io.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkMatrix3x3.h>
#include <vtkMetaImageReader.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkStreamingDemandDrivenPipeline.h>
#include <vtkXMLImageDataReader.h>

#include "io/inrimage.hpp"
#include "io/path_util.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace {

// A voxel grid after subsampling: value (i, j, k) at index i + nx (j + ny k), at origin + (i, j, k) * spacing.
struct VoxelGrid {
  uint64_t dims[3] = {0, 0, 0};
  glm::dvec3 origin{0.0};
  glm::dvec3 spacing{1.0};
  std::vector<double> values;
};

bool is_inr_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  if (ext == ".inr") return true;
  return ext == ".gz" && detail::lower_extension(std::filesystem::path(path).stem().string()) == ".inr";
}

uint64_t kept(uint64_t n, uint32_t subsample) { return (n - 1) / subsample + 1; }

// The guard runs on the header alone, before the voxels are read.
void check_size(const std::string& path, const uint64_t dims[3], const ImageReadOptions& options) {
  const std::string shape = std::to_string(dims[0]) + " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]);
  if (options.subsample == 0) throw InputError(path, "subsample must be at least 1");
  for (int a = 0; a < 3; ++a)
    if (kept(dims[a], options.subsample) < 2)
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
    if (__builtin_mul_overflow(points, kept(dims[a], options.subsample), &points)) points = std::numeric_limits<uint64_t>::max();
  if (points > std::numeric_limits<uint32_t>::max())
    throw InputError(path, "the image has more voxels than 32-bit point indices can address; subsample it");
}

VoxelGrid read_inr(const std::string& path, const ImageReadOptions& options) {
  if (!options.array.empty())
    throw InputError(path, "INRIMAGE files hold one unnamed array; no array '" + options.array + "' to choose");
  const detail::InrHeader header = detail::read_inr_header(path);
  check_size(path, header.dims, options);
  VoxelGrid grid;
  for (int a = 0; a < 3; ++a) grid.dims[a] = kept(header.dims[a], options.subsample);
  grid.origin = header.origin;
  grid.spacing = header.spacing * double(options.subsample);
  grid.values = detail::read_inr_voxels(path, header, options.subsample);
  return grid;
}

std::string point_array_names(vtkPointData* data) {
  std::string names;
  for (int i = 0; i < data->GetNumberOfArrays(); ++i) {
    const char* n = data->GetArrayName(i);
    names += std::string(names.empty() ? "" : ", ") + (n ? n : "(unnamed)");
  }
  return names.empty() ? "none" : names;
}

// VTK's image readers report some failures (a truncated MetaImage .raw) only as an ErrorEvent,
// leaving the error code at 0: the observer keeps the first message.
void keep_first_error(vtkObject*, unsigned long, void* first_error, void* message) {
  auto* kept_message = static_cast<std::string*>(first_error);
  if (kept_message->empty()) *kept_message = message ? static_cast<const char*>(message) : "unknown error";
}

// MetaIO, under vtkMetaImageReader, reports a truncated .raw only on std::cerr and hands VTK a
// partly filled image; while a reader runs, its cerr output is kept here and counts as a failure.
class CerrCapture {
 public:
  CerrCapture() : previous_(std::cerr.rdbuf(text_.rdbuf())) {}
  ~CerrCapture() { std::cerr.rdbuf(previous_); }
  CerrCapture(const CerrCapture&) = delete;
  CerrCapture& operator=(const CerrCapture&) = delete;
  std::string first_line() const {
    std::istringstream in(text_.str());
    std::string line;
    std::getline(in >> std::ws, line);
    return line;
  }

 private:
  std::ostringstream text_;
  std::streambuf* previous_;
};

template <typename Reader>
VoxelGrid read_vtk_image(const std::string& path, const ImageReadOptions& options, const char* format) {
  vtkNew<Reader> reader;
  std::string vtk_error;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetCallback(keep_first_error);
  on_error->SetClientData(&vtk_error);
  reader->AddObserver(vtkCommand::ErrorEvent, on_error);
  const CerrCapture metaio_messages;
  auto failure = [&]() -> std::string {  // empty while nothing went wrong
    if (!vtk_error.empty()) return vtk_error;
    if (const std::string line = metaio_messages.first_line(); !line.empty()) return line;
    return reader->GetErrorCode() != 0 ? "error code " + std::to_string(reader->GetErrorCode()) : "";
  };
  if (!reader->CanReadFile(path.c_str())) throw InputError(path, std::string("is not a ") + format + " file");
  reader->SetFileName(path.c_str());
  reader->UpdateInformation();
  if (const std::string problem = failure(); !problem.empty())
    throw InputError(path, std::string("VTK could not read the header of this ") + format + " file: " + problem);
  int extent[6];
  reader->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  uint64_t full[3];
  for (int a = 0; a < 3; ++a) full[a] = extent[2 * a + 1] >= extent[2 * a] ? uint64_t(extent[2 * a + 1] - extent[2 * a] + 1) : 0;
  if (full[0] == 0 || full[1] == 0 || full[2] == 0)
    throw InputError(path, std::string("VTK could not read any voxels from this ") + format + " file (empty or corrupt?)");
  check_size(path, full, options);

  reader->Update();
  vtkImageData* image = reader->GetOutput();
  if (const std::string problem = failure(); !problem.empty())
    throw InputError(path, std::string("VTK could not read the ") + format + " image: " + problem);
  if (!image || uint64_t(image->GetNumberOfPoints()) != full[0] * full[1] * full[2])
    throw InputError(path, std::string("VTK could not read the ") + format + " image (corrupt or truncated file?)");
  vtkMatrix3x3* direction = image->GetDirectionMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (direction->GetElement(r, c) != (r == c ? 1.0 : 0.0))
        throw InputError(path, "has a rotated grid (a direction matrix other than the identity), which is not supported");

  vtkPointData* point_data = image->GetPointData();
  vtkDataArray* array = nullptr;
  if (!options.array.empty()) array = point_data->GetArray(options.array.c_str());
  else array = point_data->GetScalars() ? point_data->GetScalars() : (point_data->GetNumberOfArrays() == 1 ? point_data->GetArray(0) : nullptr);
  if (!array)
    throw InputError(path, (options.array.empty() ? std::string("has no active scalars to use; choose an array")
                                                  : "has no point array '" + options.array + "'") +
                               " (point arrays: " + point_array_names(point_data) + ")");

  VoxelGrid grid;
  const double* origin = image->GetOrigin();
  const double* spacing = image->GetSpacing();
  for (int a = 0; a < 3; ++a) {
    grid.dims[a] = kept(full[a], options.subsample);
    grid.origin[a] = origin[a] + extent[2 * a] * spacing[a];
    grid.spacing[a] = spacing[a] * options.subsample;
  }
  grid.values.reserve(grid.dims[0] * grid.dims[1] * grid.dims[2]);
  const int components = array->GetNumberOfComponents();
  const uint32_t s = options.subsample;
  for (uint64_t k = 0; k < full[2]; k += s)
    for (uint64_t j = 0; j < full[1]; j += s)
      for (uint64_t i = 0; i < full[0]; i += s) {
        const vtkIdType id = vtkIdType(i + full[0] * (j + full[1] * k));
        double v = 0.0;
        if (components == 1) v = array->GetComponent(id, 0);
        else {  // vectors by magnitude
          for (int c = 0; c < components; ++c) v += array->GetComponent(id, c) * array->GetComponent(id, c);
          v = std::sqrt(v);
        }
        if (!std::isfinite(v)) throw InputError(path, "array '" + std::string(array->GetName() ? array->GetName() : "") + "' holds a non-finite value");
        grid.values.push_back(v);
      }
  return grid;
}

TetMesh tetrahedralize(const VoxelGrid& grid, const std::string& name, const ImageReadOptions& options) {
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

  // Kuhn split: the six monotone paths from corner 000 to corner 111 along the cell's edges. Every
  // cell is a translate of cell (0,0,0), so its six tetrahedra, as index offsets from the cell's
  // first corner and oriented positively, are worked out once there.
  static const int kPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::array<uint32_t, 4> offsets[6];
  for (int p = 0; p < 6; ++p) {
    uint64_t c[3] = {0, 0, 0};
    offsets[p][0] = 0;
    for (int s = 0; s < 3; ++s) {
      ++c[kPaths[p][s]];
      offsets[p][size_t(s) + 1] = point_index(c[0], c[1], c[2]);
    }
    const auto& o = offsets[p];
    if (signed_volume(mesh.points[o[0]], mesh.points[o[1]], mesh.points[o[2]], mesh.points[o[3]]) < 0.0) std::swap(offsets[p][2], offsets[p][3]);
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
    mesh.point_extinction.resize(grid.values.size());
    for (size_t i = 0; i < grid.values.size(); ++i) mesh.point_extinction[i] = grid.values[i] * options.density_scale;
    mesh.cell_extinction.reserve(mesh.tets.size());
    for (const auto& tet : mesh.tets) {  // the cell's mean, for statistics; rendering interpolates the points
      double sigma = 0.0;
      for (uint32_t v : tet) sigma += 0.25 * mesh.point_extinction[v];
      mesh.cell_extinction.push_back(sigma);
    }
  } else {
    mesh.cell_extinction.assign(mesh.tets.size(), options.density_scale);
  }
  return mesh;
}

}  // namespace

uint64_t image_tet_count(const uint64_t dims[3], uint32_t subsample) {
  uint64_t count = 6;  // saturates rather than wrapping, for headers with absurd sizes
  for (int a = 0; a < 3; ++a)
    if (__builtin_mul_overflow(count, kept(dims[a], subsample) - 1, &count)) return std::numeric_limits<uint64_t>::max();
  return count;
}

bool is_image_volume_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  return ext == ".vti" || ext == ".mhd" || ext == ".mha" || is_inr_path(path);
}

TetMesh read_image_volume(const std::string& path, const ImageReadOptions& options) {
  if (!std::filesystem::exists(path)) throw InputError(path, "file does not exist");
  if (!is_image_volume_path(path))
    throw InputError(path, "unknown image type '" + detail::lower_extension(path) + "' (this build reads .vti, .mhd, .mha, .inr, .inr.gz)");
  vtkObject::GlobalWarningDisplayOff();  // failures become InputErrors, not console noise
  const std::string ext = detail::lower_extension(path);
  VoxelGrid grid = ext == ".vti"   ? read_vtk_image<vtkXMLImageDataReader>(path, options, "VTK XML image data (.vti)")
                   : is_inr_path(path) ? read_inr(path, options)
                                       : read_vtk_image<vtkMetaImageReader>(path, options, "MetaImage (.mhd/.mha)");
  TetMesh mesh = tetrahedralize(grid, path, options);
  validate(mesh);
  return mesh;
}

}  // namespace prismoid::io
