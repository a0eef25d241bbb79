#include "io/exodus_io.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include <vtkCellTypes.h>
#include <vtkCompositeDataSet.h>
#include <vtkExodusIIReader.h>
#include <vtkGenericCell.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkNew.h>
#include <vtkStreamingDemandDrivenPipeline.h>

#include "io/declared_sizes.hpp"
#include "io/isolated_read.hpp"
#include "io/path_util.hpp"
#include "io/vtk_grid.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

template <typename S, Carries<ExodusInfo> M>
void fields(S& s, M& info) {
  s(info.blocks);
  s(info.nodal_variables);
  s(info.element_variables);
  s(info.times);
  s(info.node_sets);
  s(info.side_sets);
}

namespace {

using Exodus = vtkExodusIIReader;

std::string number_text(double v) {
  std::ostringstream out;
  out.precision(9);
  out << v;
  return out.str();
}

std::string plural(size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// The reader with the file's metadata read: blocks, variables, times. VTK's id arrays are left
// out: they would be arrays a scalar field could be chosen from (io/vtk_tet_io.hpp), and
// ParaView's users do not colour by them.
vtkSmartPointer<Exodus> open_exodus(const std::string& path, detail::ErrorCatcher* errors) {
  detail::check_declared_sizes(path);
  auto reader = vtkSmartPointer<Exodus>::New();
  if (!reader->CanReadFile(path.c_str()))
    throw InputError(path, "is not an Exodus II file (VTK's Exodus reader cannot open it: not netCDF, or not Exodus)");
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->SetFileName(path.c_str());
  reader->GenerateObjectIdCellArrayOff();
  reader->GenerateGlobalElementIdArrayOff();
  reader->GenerateGlobalNodeIdArrayOff();
  reader->GenerateImplicitElementIdArrayOff();
  reader->GenerateImplicitNodeIdArrayOff();
  reader->GenerateFileIdArrayOff();
  reader->UpdateInformation();
  if (reader->GetErrorCode() != 0 || !errors->message.empty() || !detail::reported_vtk_error().empty())
    detail::fail_read(path, "VTK could not read the Exodus II file's metadata (truncated or corrupt?)", *errors);
  return reader;
}

// The time values, checked: finite and increasing.
std::vector<double> checked_times(const std::string& path, Exodus* reader) {
  vtkInformation* out = reader->GetOutputInformation(0);
  std::vector<double> times;
  if (out->Has(vtkStreamingDemandDrivenPipeline::TIME_STEPS())) {
    const double* t = out->Get(vtkStreamingDemandDrivenPipeline::TIME_STEPS());
    times.assign(t, t + out->Length(vtkStreamingDemandDrivenPipeline::TIME_STEPS()));
  }
  for (size_t i = 0; i < times.size(); ++i) {
    if (!std::isfinite(times[i]))
      throw InputError(path, "time step " + std::to_string(i) + " has the time value " + number_text(times[i]) + ", not a finite number");
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InputError(path, "time step " + std::to_string(i) + " (t = " + number_text(times[i]) + ") does not come after step " +
                                 std::to_string(i - 1) + " (t = " + number_text(times[i - 1]) + "): time values must increase");
  }
  return times;
}

std::vector<ExodusBlock> listed_blocks(Exodus* reader) {
  std::vector<ExodusBlock> blocks;
  for (int b = 0; b < reader->GetNumberOfObjects(Exodus::ELEM_BLOCK); ++b) {
    ExodusBlock block;
    block.id = reader->GetObjectId(Exodus::ELEM_BLOCK, b);
    const char* name = reader->GetObjectName(Exodus::ELEM_BLOCK, b);
    block.name = name ? name : "";
    block.cells = size_t(std::max(0, reader->GetNumberOfEntriesInObject(Exodus::ELEM_BLOCK, b)));
    blocks.push_back(block);
  }
  return blocks;
}

// Reads the enabled blocks; one grid per element block, null where a block was not enabled.
std::vector<vtkSmartPointer<vtkUnstructuredGrid>> read_blocks(const std::string& path, Exodus* reader, const detail::ErrorCatcher& errors,
                                                             const Progress& progress, const detail::ProgressSpan& span) {
  detail::update_with_progress(reader, progress, span, path);
  if (reader->GetErrorCode() != 0 || !errors.message.empty() || !detail::reported_vtk_error().empty())
    detail::fail_read(path, "VTK could not read the Exodus II file (truncated or corrupt?)", errors);
  auto* all = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  if (!all) throw InputError(path, "VTK's Exodus reader gave no data");
  vtkMultiBlockDataSet* elements = nullptr;  // the "Element Blocks" group, found by name rather than by position
  for (unsigned i = 0; i < all->GetNumberOfBlocks(); ++i) {
    vtkInformation* meta = all->HasMetaData(i) ? all->GetMetaData(i) : nullptr;
    if (meta && meta->Has(vtkCompositeDataSet::NAME()) && std::string(meta->Get(vtkCompositeDataSet::NAME())) == "Element Blocks")
      elements = vtkMultiBlockDataSet::SafeDownCast(all->GetBlock(i));
  }
  std::vector<vtkSmartPointer<vtkUnstructuredGrid>> grids(size_t(reader->GetNumberOfObjects(Exodus::ELEM_BLOCK)));
  for (unsigned b = 0; elements && b < elements->GetNumberOfBlocks() && b < grids.size(); ++b)
    grids[b] = vtkUnstructuredGrid::SafeDownCast(elements->GetBlock(b));
  return grids;
}

// The block's cell class and whether it holds 3D cells (Exodus blocks hold one element type).
void describe_cells(vtkUnstructuredGrid* grid, ExodusBlock& block) {
  if (!grid || grid->GetNumberOfCells() == 0) return;
  std::set<int> types;
  for (vtkIdType c = 0; c < grid->GetNumberOfCells(); ++c) types.insert(grid->GetCellType(c));
  for (int type : types) {
    if (block.cell_type.empty()) block.cell_type = vtkCellTypes::GetClassNameFromTypeId(type);
    vtkSmartPointer<vtkCell> cell;
    cell.TakeReference(vtkGenericCell::InstantiateCell(type));
    if (cell && cell->GetCellDimension() == 3) block.solid = true;
  }
}

std::string block_list(const std::vector<ExodusBlock>& blocks) {
  std::string list;
  for (const ExodusBlock& b : blocks) {
    list.append(list.empty() ? "" : ", ").append(block_label(b));
    if (!b.cell_type.empty()) list.append(" (").append(b.cell_type).append(")");
  }
  return list.empty() ? "none" : list;
}

struct InfoRequest {
  std::string path;
  bool cells = true;
};
template <typename S, Carries<InfoRequest> M>
void fields(S& s, M& r) {
  s(r.path);
  s(r.cells);
}

ExodusInfo exodus_info_here(const std::string& path, bool cells) {
  const detail::QuietVtk quiet;
  vtkNew<detail::ErrorCatcher> errors;
  vtkSmartPointer<Exodus> reader = open_exodus(path, errors);
  ExodusInfo info;
  info.times = checked_times(path, reader);
  info.blocks = listed_blocks(reader);
  for (int i = 0; i < reader->GetNumberOfObjectArrays(Exodus::NODAL); ++i)
    info.nodal_variables.emplace_back(reader->GetObjectArrayName(Exodus::NODAL, i));
  for (int i = 0; i < reader->GetNumberOfObjectArrays(Exodus::ELEM_BLOCK); ++i)
    info.element_variables.emplace_back(reader->GetObjectArrayName(Exodus::ELEM_BLOCK, i));
  info.node_sets = size_t(std::max(0, reader->GetNumberOfObjects(Exodus::NODE_SET)));
  info.side_sets = size_t(std::max(0, reader->GetNumberOfObjects(Exodus::SIDE_SET)));
  if (!cells) return info;
  for (size_t b = 0; b < info.blocks.size(); ++b) reader->SetObjectStatus(Exodus::ELEM_BLOCK, int(b), 1);
  const auto grids = read_blocks(path, reader, *errors, {}, {});  // the cells only: no variables enabled
  for (size_t b = 0; b < info.blocks.size(); ++b) describe_cells(grids[b], info.blocks[b]);
  return info;
}

const ChildWork<InfoRequest, ExodusInfo> kExodusInfo("exodus-info",
                                                     [](const InfoRequest& r, const Progress&) { return exodus_info_here(r.path, r.cells); });

// The indices of the blocks `tokens` name, each by id or name.
std::vector<size_t> named_blocks(const std::string& path, const std::vector<ExodusBlock>& blocks, const std::vector<std::string>& tokens) {
  std::vector<size_t> chosen;
  for (const std::string& token : tokens) {
    size_t found = blocks.size();
    for (size_t b = 0; b < blocks.size() && found == blocks.size(); ++b)
      if (token == blocks[b].name || token == std::to_string(blocks[b].id)) found = b;
    if (found == blocks.size())
      throw InputError("--blocks", "'" + token + "' names no element block of " + path + " (its blocks, by id and name: " + block_list(blocks) + ")");
    if (std::find(chosen.begin(), chosen.end(), found) == chosen.end()) chosen.push_back(found);
  }
  return chosen;
}

}  // namespace

bool is_exodus_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  return ext == ".exo" || ext == ".e" || ext == ".ex2" || ext == ".exii" || ext == ".g" || ext == ".gen";
}

std::string block_label(const ExodusBlock& block) {
  const std::string id = std::to_string(block.id);
  return block.name.empty() || block.name.rfind("Unnamed block ID: " + id, 0) == 0 ? id : id + " '" + block.name + "'";
}

ExodusInfo read_exodus_info(const std::string& path, bool cells) {
  detail::require_regular_file(path);
  return kExodusInfo(read_job(path), {}, {path, cells});
}

namespace detail {

GridSource read_exodus_grid(const std::string& path, const GridChoice& choice, const Progress& progress, double read_end) {
  require_regular_file(path);
  vtkNew<ErrorCatcher> errors;
  vtkSmartPointer<Exodus> reader = open_exodus(path, errors);
  const std::vector<double> times = checked_times(path, reader);
  if (choice.time_step > 0 && choice.time_step >= times.size())
    throw InputError("--time-step", path + " has " + plural(times.size(), "time step", "time steps") + "; step " +
                                        std::to_string(choice.time_step) + " does not exist");
  std::vector<ExodusBlock> blocks = listed_blocks(reader);
  if (blocks.empty()) throw InputError(path, "has no element blocks: nothing to draw");
  const bool named = !choice.blocks.empty();
  const std::vector<size_t> chosen = named ? named_blocks(path, blocks, choice.blocks) : std::vector<size_t>();
  for (size_t b = 0; b < blocks.size(); ++b)
    reader->SetObjectStatus(Exodus::ELEM_BLOCK, int(b), !named || std::find(chosen.begin(), chosen.end(), b) != chosen.end());
  reader->SetAllArrayStatus(Exodus::NODAL, 1);
  reader->SetAllArrayStatus(Exodus::ELEM_BLOCK, 1);
  reader->SetTimeStep(int(choice.time_step));
  const auto grids = read_blocks(path, reader, *errors, progress, {0.0, 0.8 * read_end, "reading blocks"});

  GridSource source;
  std::vector<vtkUnstructuredGrid*> solid;
  for (size_t b = 0; b < blocks.size(); ++b) {
    ExodusBlock& block = blocks[b];
    if (named && std::find(chosen.begin(), chosen.end(), b) == chosen.end()) continue;
    describe_cells(grids[b], block);
    if (block.solid) {
      solid.push_back(grids[b]);
    } else if (named) {
      throw InputError(path, "block " + block_label(block) + " holds " +
                                 (block.cell_type.empty() ? std::string("no cells") : block.cell_type + " cells, no 3D cells") +
                                 ": it cannot be drawn as a volume");
    } else {
      source.ignored.push_back("block " + block_label(block) + " (" + (block.cell_type.empty() ? std::string("empty") : block.cell_type + ": no 3D cells") + ")");
    }
  }
  if (solid.empty()) throw InputError(path, "has no element block with 3D cells (its blocks: " + block_list(blocks) + ")");
  const size_t node_sets = size_t(std::max(0, reader->GetNumberOfObjects(Exodus::NODE_SET)));
  const size_t side_sets = size_t(std::max(0, reader->GetNumberOfObjects(Exodus::SIDE_SET)));
  if (node_sets + side_sets > 0)
    source.ignored.push_back((node_sets ? plural(node_sets, "node set", "node sets") : std::string()) + (node_sets && side_sets ? " and " : "") +
                             (side_sets ? plural(side_sets, "side set", "side sets") : std::string()) + " (element blocks are drawn)");
  if (solid.size() == 1) {  // as the file holds it, as a .vtu's one grid is read
    source.grid = solid.front();
    return source;
  }
  GridSource merged = merge_pieces(path, solid, progress, {0.8 * read_end, read_end, "merging blocks"});
  merged.ignored = source.ignored;
  return merged;
}

}  // namespace detail

}  // namespace prismoid::io
