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

#include "io/declared_sizes.hpp"
#include "io/inrimage.hpp"
#include "io/isolated_read.hpp"
#include "io/path_util.hpp"
#include "io/vtk_grid.hpp"
#include "io/vtk_progress.hpp"
#include "io/voxel_tets.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace {

bool is_inr_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  if (ext == ".inr") return true;
  return ext == ".gz" && detail::lower_extension(std::filesystem::path(path).stem().string()) == ".inr";
}

detail::VoxelGrid read_inr(const std::string& path, const ImageReadOptions& options) {
  if (!options.array.empty())
    throw InputError(path, "INRIMAGE files hold one unnamed array; no array '" + options.array + "' to choose");
  const detail::InrHeader header = detail::read_inr_header(path);
  detail::check_image_size(path, header.dims, options);
  detail::VoxelGrid grid;
  for (int a = 0; a < 3; ++a) grid.dims[a] = detail::kept_voxels(header.dims[a], options.subsample);
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
detail::VoxelGrid read_vtk_image(const std::string& path, const ImageReadOptions& options, const char* format) {
  vtkNew<Reader> reader;
  std::string vtk_error;
  vtkNew<vtkCallbackCommand> on_error;
  on_error->SetCallback(keep_first_error);
  on_error->SetClientData(&vtk_error);
  reader->AddObserver(vtkCommand::ErrorEvent, on_error);
  const CerrCapture metaio_messages;
  auto failure = [&]() -> std::string {  // empty while nothing went wrong
    if (!vtk_error.empty()) return detail::vtk_problem(vtk_error);
    if (const std::string reported = detail::reported_vtk_error(); !reported.empty()) return detail::vtk_problem(reported);
    if (const std::string line = metaio_messages.first_line(); !line.empty()) return line;
    return reader->GetErrorCode() != 0 ? "error code " + std::to_string(reader->GetErrorCode()) : "";
  };
  if (!reader->CanReadFile(path.c_str())) throw InputError(path, std::string("is not a ") + format + " file");
  detail::check_declared_sizes(path);
  reader->SetFileName(path.c_str());
  reader->UpdateInformation();
  if (const std::string problem = failure(); !problem.empty())
    throw InputError(path, std::string("VTK could not read the header of this ") + format + " file: " + problem);
  // A header VTK could not parse sets no extent at all: it then stays empty, never uninitialized.
  int extent[6] = {0, -1, 0, -1, 0, -1};
  if (vtkInformation* info = reader->GetOutputInformation(0); info && info->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
    info->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
  uint64_t full[3];
  for (int a = 0; a < 3; ++a) full[a] = extent[2 * a + 1] >= extent[2 * a] ? uint64_t(extent[2 * a + 1] - extent[2 * a] + 1) : 0;
  if (full[0] == 0 || full[1] == 0 || full[2] == 0)
    throw InputError(path, std::string("VTK could not read any voxels from this ") + format + " file (empty or corrupt?)");
  detail::check_image_size(path, full, options);

  detail::update_with_progress(reader, options.progress, {0.0, 0.5, "reading voxels"}, path);
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

  detail::VoxelGrid grid;
  const double* origin = image->GetOrigin();
  const double* spacing = image->GetSpacing();
  for (int a = 0; a < 3; ++a) {
    grid.dims[a] = detail::kept_voxels(full[a], options.subsample);
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

// What the reader child needs: the path and the options (their progress is the child's own).
struct ImageRequest {
  std::string path;
  ImageReadOptions options;
};
template <typename S, Carries<ImageRequest> M>
void fields(S& s, M& r) {
  s(r.path);
  s(r.options.array);
  s(r.options.role);
  s(r.options.density_scale);
  s(r.options.subsample);
  s(r.options.max_cells);
}

const ChildWork<ImageRequest, TetMesh> kReadImageVolume("read-image-volume", [](const ImageRequest& request, const Progress& progress) {
  const std::string& path = request.path;
  const detail::QuietVtk quiet;  // failures become InputErrors, not console noise
  ImageReadOptions reading = request.options;
  reading.progress = progress;
  const std::string ext = detail::lower_extension(path);
  detail::VoxelGrid grid = ext == ".vti"       ? read_vtk_image<vtkXMLImageDataReader>(path, reading, "VTK XML image data (.vti)")
                           : is_inr_path(path) ? read_inr(path, reading)
                                               : read_vtk_image<vtkMetaImageReader>(path, reading, "MetaImage (.mhd/.mha)");
  // VTK's readers take the first half of the bar; INRIMAGE's reading is not reported.
  ImageReadOptions converting = reading;
  converting.progress = scaled(progress, 0.5, 1.0);
  TetMesh mesh = detail::voxel_grid_to_tets(grid, path, converting);
  validate(mesh);
  return mesh;
});

}  // namespace

bool is_image_volume_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  return ext == ".vti" || ext == ".mhd" || ext == ".mha" || is_inr_path(path);
}

TetMesh read_image_volume(const std::string& path, const ImageReadOptions& options) {
  detail::require_regular_file(path);
  if (!is_image_volume_path(path))
    throw InputError(path, "unknown image type '" + detail::lower_extension(path) + "' (this build reads .vti, .mhd, .mha, .inr, .inr.gz)");
  // The readers and the conversion run in a child process (io/isolated_read.hpp).
  return kReadImageVolume(read_job(path), options.progress, {path, options});
}

}  // namespace prismoid::io
