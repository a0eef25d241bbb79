#pragma once
// Internal to io/: VTK unstructured grids from every file kind we read, and their
// tetrahedralization. Only io/ sources include this header (it exposes VTK types).
#include <cstddef>
#include <string>
#include <vector>

#include <vtkCommand.h>
#include <vtkOutputWindow.h>
#include <vtkSmartPointer.h>
#include <vtkUnstructuredGrid.h>

#include "io/progress.hpp"
#include "io/vtk_progress.hpp"

namespace prismoid::io::detail {

// While alive, VTK's error events reach the readers' observers (so they become InputErrors)
// and nothing VTK says reaches the console. VTK's output window is process-wide: io reads on
// one thread at a time.
class QuietVtk {
 public:
  QuietVtk();
  ~QuietVtk();
  QuietVtk(const QuietVtk&) = delete;
  QuietVtk& operator=(const QuietVtk&) = delete;

 private:
  vtkSmartPointer<vtkOutputWindow> previous_;
  int display_;
  int logger_verbosity_ = 0;
};

// The first error VTK reported through its output window since the innermost QuietVtk began
// (objects with an error observer report there instead); empty when none.
std::string reported_vtk_error();
// The problem a VTK message states, without its file, line and object prefixes.
std::string vtk_problem(std::string text);

// VTK reports read failures as error events, not return codes: this collects the first
// message of an algorithm (and of the readers it runs for the pieces) so it can name the problem.
class ErrorCatcher : public vtkCommand {
 public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    if (message.empty() && data) message = static_cast<const char*>(data);
  }
  std::string message;
};

// InputError(path, what), with VTK's own words for the problem where it gave some.
[[noreturn]] void fail_read(const std::string& path, const std::string& what, const ErrorCatcher& errors);

struct GridSource {
  vtkSmartPointer<vtkUnstructuredGrid> grid;
  size_t pieces = 1;           // blocks of a .vtm or pieces of a .pvtu, merged into `grid`
  size_t merged_points = 0;    // coincident points shared between pieces, merged into one
  std::vector<std::string> ignored;  // what the file holds that is not drawn (MeshConversion::ignored)
  std::vector<std::string> blocks;   // a .vtm's blocks, one line each, e.g. "block 1 'density': vtkImageData (not drawn)"
};

// Which part of a file with several: the blocks of a .vtm or an Exodus II file and the time step
// of an Exodus II file (TetReadOptions::blocks and ::time_step).
struct GridChoice {
  std::vector<std::string> blocks;
  uint32_t time_step = 0;
};

// One grid of several with coincident points merged: neighbouring pieces then share point ids.
GridSource merge_pieces(const std::string& path, const std::vector<vtkUnstructuredGrid*>& pieces, const Progress& progress,
                        const ProgressSpan& span);

// An Exodus II file's chosen element blocks at one time step, merged (io/exodus_io.cpp).
GridSource read_exodus_grid(const std::string& path, const GridChoice& choice, const Progress& progress, double read_end);

// .vtu, legacy .vtk, Exodus II, .vtm (its unstructured grid blocks; others are noted) or .pvtu. Pieces are
// appended with coincident points merged, so cells of neighbouring pieces share point ids
// (the ordered triangulation below is conforming only across faces with shared ids).
// InputError naming the file and the problem. `progress` sees fractions 0 to `read_end` while VTK
// reads (and merges pieces); returning false cancels (Cancelled).
// An Exodus II file (io/exodus_io.hpp): the blocks and step `choice` names.
GridSource read_unstructured_grid(const std::string& path, const Progress& progress = {}, double read_end = 1.0,
                                  const GridChoice& choice = {});

// Every 3D cell as tetrahedra through vtkDataSetTriangleFilter; lower-dimensional cells are
// dropped. Cell data is copied to each cell's tetrahedra, points and point data pass through.
// `progress` sees fractions from `start` to `end`; returning false cancels (Cancelled(path)).
vtkSmartPointer<vtkUnstructuredGrid> tetrahedralize(vtkUnstructuredGrid* grid, const std::string& path, const Progress& progress = {},
                                                    double start = 0.0, double end = 1.0);

// Higher-order cells as tetrahedra through VTK's vtkTessellatorFilter: each edge halved up to
// `levels` times where the cell's shape or a point array is not linear along it; points merged
// (neighbours share their new points), point and cell arrays kept. Progress from `start` to `end`.
vtkSmartPointer<vtkUnstructuredGrid> tessellate(vtkUnstructuredGrid* grid, const std::string& path, uint32_t levels,
                                                const Progress& progress = {}, double start = 0.0, double end = 1.0);

}  // namespace prismoid::io::detail

#include "io/isolated_read.hpp"
#include "io/vtk_tet_io.hpp"

namespace prismoid::io {

// MeshConversion through the isolated reader's pipe (io/isolated_read.hpp).
template <typename S, Carries<MeshConversion> M>
void fields(S& s, M& c) {
  s(c.cells_in);
  s(c.dropped);
  s(c.tets_out);
  s(c.pieces);
  s(c.merged_points);
  s(c.zero_volume);
  s(c.inverted);
  s(c.chosen_array);
  s(c.chosen_why);
  s(c.ignored);
  s(c.higher_order);
  s(c.subdivision);
}

}  // namespace prismoid::io

namespace prismoid::io::detail {

// The tetrahedral mesh of a grid read from `path` (split as MeshConversion describes).
TetMesh tet_mesh_from_grid(const GridSource& source, const std::string& path, const TetReadOptions& options,
                           MeshConversion* conversion);

}  // namespace prismoid::io::detail
