#include "io/vtk_grid.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include <vtkAppendFilter.h>
#include <vtkCommand.h>
#include <vtkDataObjectTreeIterator.h>
#include <vtkDataSetTriangleFilter.h>
#include <vtkDataArray.h>
#include <vtkPointData.h>
#include <vtkTessellatorFilter.h>
#include <vtkInformation.h>
#include <vtkMultiBlockDataSet.h>
#include <vtkLogger.h>
#include <vtkNew.h>
#include <vtkOutputWindow.h>
#include <vtkUnstructuredGridReader.h>
#include <vtkXMLMultiBlockDataReader.h>
#include <vtkXMLPUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridReader.h>

#include "io/declared_sizes.hpp"
#include "io/exodus_io.hpp"
#include "io/path_util.hpp"
#include "io/vtk_progress.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io::detail {

namespace {

// Messages from VTK objects without an observer: kept from the console while io reads, and the
// first error kept. VTK's readers report some failures only this way: errors of objects without
// an observer, and "generic warnings" of the helper functions that read values (a legacy file's
// data ending early is one, "Error reading ascii data"). A read during which one came failed.
class SilentOutput : public vtkOutputWindow {
 public:
  static SilentOutput* New() { return new SilentOutput; }
  void DisplayText(const char*) override {}
  void DisplayErrorText(const char* text) override { keep(text); }
  void DisplayGenericWarningText(const char* text) override { keep(text); }
  std::string first_error;

 private:
  void keep(const char* text) {
    if (first_error.empty() && text) first_error = text;
  }
};

template <typename Reader>
vtkSmartPointer<Reader> run_xml_reader(const std::string& path, const char* kind, const Progress& progress, const ProgressSpan& span) {
  auto reader = vtkSmartPointer<Reader>::New();
  if (!reader->CanReadFile(path.c_str())) throw InputError(path, std::string("is not a VTK XML ") + kind + " file");
  vtkNew<ErrorCatcher> errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  reader->SetFileName(path.c_str());
  update_with_progress(reader, progress, span, path);
  if (reader->GetErrorCode() != 0 || !errors->message.empty() || !reported_vtk_error().empty() || !reader->GetOutputDataObject(0))
    fail_read(path, "VTK could not read the file (truncated or corrupt?)", *errors);
  return reader;
}

vtkSmartPointer<vtkUnstructuredGrid> read_legacy(const std::string& path, const Progress& progress, const ProgressSpan& span) {
  vtkNew<vtkUnstructuredGridReader> reader;
  reader->SetFileName(path.c_str());
  if (!reader->OpenVTKFile() || !reader->ReadHeader()) throw InputError(path, "is not a legacy VTK file");
  reader->CloseVTKFile();
  if (!reader->IsFileUnstructuredGrid()) throw InputError(path, "is a legacy VTK file but not an UNSTRUCTURED_GRID");
  vtkNew<ErrorCatcher> errors;
  reader->AddObserver(vtkCommand::ErrorEvent, errors);
  update_with_progress(reader, progress, span, path);
  if (reader->GetErrorCode() != 0 || !errors->message.empty() || !reported_vtk_error().empty() || !reader->GetOutput())
    fail_read(path, "VTK could not read the unstructured grid (truncated or corrupt?)", *errors);
  return reader->GetOutput();
}

// A .vtm's leaves in the order VTK's tree iterator visits them (their index), each named by its
// metadata where it has a name; the chosen ones (choice.blocks: by index or name; none: all) that
// are unstructured grids are merged. A leaf of another kind is named in a note, or refused when
// chosen by name.
GridSource read_multiblock(const std::string& path, const GridChoice& choice, const Progress& progress, double read_end) {
  auto reader = run_xml_reader<vtkXMLMultiBlockDataReader>(path, "multiblock (.vtm)", progress, {0.0, 0.8 * read_end, "reading blocks"});
  auto* tree = vtkMultiBlockDataSet::SafeDownCast(reader->GetOutputDataObject(0));
  if (!tree) throw InputError(path, "VTK did not read a multiblock data set");
  struct Leaf {
    vtkDataObject* data = nullptr;
    std::string label;  // "1 'density'" or "1"
    std::string name;
  };
  std::vector<Leaf> leaves;
  vtkSmartPointer<vtkDataObjectTreeIterator> it;
  it.TakeReference(tree->NewTreeIterator());
  it->VisitOnlyLeavesOn();
  it->SkipEmptyNodesOff();
  for (it->InitTraversal(); !it->IsDoneWithTraversal(); it->GoToNextItem()) {
    Leaf leaf;
    leaf.data = it->GetCurrentDataObject();
    vtkInformation* meta = it->HasCurrentMetaData() ? it->GetCurrentMetaData() : nullptr;
    if (meta && meta->Has(vtkCompositeDataSet::NAME())) leaf.name = meta->Get(vtkCompositeDataSet::NAME());
    leaf.label = std::to_string(leaves.size()) + (leaf.name.empty() ? std::string() : " '" + leaf.name + "'");
    leaves.push_back(leaf);
  }
  const auto kind = [](const Leaf& leaf) { return std::string(leaf.data ? leaf.data->GetClassName() : "empty block"); };
  std::vector<bool> chosen(leaves.size(), choice.blocks.empty());
  for (const std::string& token : choice.blocks) {
    size_t found = leaves.size();
    for (size_t i = 0; i < leaves.size() && found == leaves.size(); ++i)
      if (token == std::to_string(i) || (!leaves[i].name.empty() && token == leaves[i].name)) found = i;
    if (found == leaves.size()) {
      std::string list;
      for (const Leaf& leaf : leaves) list.append(list.empty() ? "" : ", ").append(leaf.label).append(" (").append(kind(leaf)).append(")");
      throw InputError("--blocks", "'" + token + "' names no block of " + path + " (its blocks, by index and name: " + (list.empty() ? "none" : list) + ")");
    }
    chosen[found] = true;
  }
  GridSource source;
  std::vector<vtkUnstructuredGrid*> grids;
  for (size_t i = 0; i < leaves.size(); ++i) {
    if (!chosen[i]) continue;
    if (auto* grid = vtkUnstructuredGrid::SafeDownCast(leaves[i].data)) {
      grids.push_back(grid);
      source.blocks.push_back("block " + leaves[i].label + ": " + std::to_string(grid->GetNumberOfCells()) + " cells");
      continue;
    }
    const std::string why = leaves[i].data ? "is a " + kind(leaves[i]) + ", not an unstructured grid (only unstructured blocks are read)" : "is empty";
    if (!choice.blocks.empty()) throw InputError(path, "block " + leaves[i].label + " " + why);
    source.ignored.push_back("block " + leaves[i].label + " (" + why + ")");
    source.blocks.push_back("block " + leaves[i].label + ": " + kind(leaves[i]) + " (not drawn)");
  }
  if (grids.empty())
    throw InputError(path, "has no unstructured grid blocks (empty mesh" + (source.ignored.empty() ? std::string(")") : "; not drawn: " + source.ignored.front() + ")"));
  GridSource merged = merge_pieces(path, grids, progress, {0.8 * read_end, read_end, "merging blocks"});
  merged.ignored = source.ignored;
  merged.blocks = source.blocks;
  return merged;
}

// The file's first bytes say what it is; a mismatch with the extension is named before a reader
// fails on it with a vaguer message.
void check_content(const std::string& path, const std::string& ext) {
  require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  std::string head(512, '\0');
  if (!in || !in.read(head.data(), std::streamsize(head.size())).gcount())
    throw InputError(path, "cannot be read (permissions?) or is empty");
  head.resize(size_t(in.gcount()));
  const bool legacy = head.rfind("# vtk DataFile", 0) == 0;
  const auto xml_at = head.find("<VTKFile");
  if (legacy && ext != ".vtk") throw InputError(path, "holds a legacy VTK file: its extension should be .vtk, not " + ext);
  if (xml_at != std::string::npos) {
    const auto type_at = head.find("type=\"", xml_at);
    const std::string type = type_at == std::string::npos ? "" : head.substr(type_at + 6, head.find('"', type_at + 6) - type_at - 6);
    const std::map<std::string, std::string> ext_of_type = {
        {"UnstructuredGrid", ".vtu"}, {"vtkMultiBlockDataSet", ".vtm"}, {"PUnstructuredGrid", ".pvtu"}};
    const auto expected = ext_of_type.find(type);
    if (expected == ext_of_type.end())
      throw InputError(path, "holds a VTK XML " + (type.empty() ? std::string("file") : type) +
                                 ", not an unstructured grid (.vtu), multiblock (.vtm) or parallel unstructured grid (.pvtu)");
    if (expected->second != ext)
      throw InputError(path, "holds a VTK XML " + type + ": its extension should be " + expected->second + ", not " + ext);
  }
}

}  // namespace

void fail_read(const std::string& path, const std::string& what, const ErrorCatcher& errors) {
  const std::string detail = vtk_problem(errors.message.empty() ? reported_vtk_error() : errors.message);
  throw InputError(path, what + (detail.empty() ? "" : " (VTK: " + detail + ")"));
}

// One grid of several with coincident points merged: neighbouring pieces then share point ids.
GridSource merge_pieces(const std::string& path, const std::vector<vtkUnstructuredGrid*>& pieces, const Progress& progress,
                        const ProgressSpan& span) {
  if (pieces.empty()) throw InputError(path, "has no unstructured grid blocks (empty mesh)");
  vtkNew<vtkAppendFilter> append;
  append->MergePointsOn();
  vtkIdType points_in = 0;
  for (vtkUnstructuredGrid* piece : pieces) {
    append->AddInputData(piece);
    points_in += piece->GetNumberOfPoints();
  }
  update_with_progress(append, progress, span, path);
  GridSource source;
  source.grid = append->GetOutput();
  source.pieces = pieces.size();
  source.merged_points = size_t(points_in - source.grid->GetNumberOfPoints());
  return source;
}

std::string vtk_problem(std::string text) {
  // "ERROR: In FILE, line N\nvtkClass (0x...): the problem" or "Generic Warning: In FILE, line
  // N\nthe problem": the problem is what the user needs.
  if (const auto newline = text.find('\n'); newline != std::string::npos && text.find(": In ") < newline) text = text.substr(newline + 1);
  if (const auto cut = text.find("): "); cut != std::string::npos && text.rfind("vtk", 0) == 0) text = text.substr(cut + 3);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

std::string reported_vtk_error() {
  auto* silent = dynamic_cast<SilentOutput*>(vtkOutputWindow::GetInstance());
  return silent ? silent->first_error : std::string();
}

QuietVtk::QuietVtk() : previous_(vtkOutputWindow::GetInstance()), display_(vtkObject::GetGlobalWarningDisplay()) {
  // Error events reach observers only while the global display is on; the silent window keeps
  // the console clean of the messages no observer takes.
  vtkObject::GlobalWarningDisplayOn();
  vtkNew<SilentOutput> silent;
  vtkOutputWindow::SetInstance(silent);
  // VTK 9 also logs each message to stderr through vtkLogger, before the output window sees
  // it. With only the stderr sink (the app adds none) the cutoff is stderr's verbosity.
  logger_verbosity_ = int(vtkLogger::GetCurrentVerbosityCutoff());
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
}

QuietVtk::~QuietVtk() {
  vtkLogger::SetStderrVerbosity(vtkLogger::Verbosity(logger_verbosity_));
  vtkOutputWindow::SetInstance(previous_);
  vtkObject::SetGlobalWarningDisplay(display_);
}

GridSource read_unstructured_grid(const std::string& path, const Progress& progress, double read_end, const GridChoice& choice) {
  const std::string ext = lower_extension(path);
  if (is_exodus_path(path)) return read_exodus_grid(path, choice, progress, read_end);
  check_content(path, ext);
  check_declared_sizes(path);
  if (ext == ".vtm") return read_multiblock(path, choice, progress, read_end);
  if (ext == ".pvtu") {
    // Read piece by piece: the reader's whole output is one grid, whose shared points
    // vtkAppendFilter would pass through unmerged.
    // The first Update reads only the summary file; the pieces come after.
    auto reader = run_xml_reader<vtkXMLPUnstructuredGridReader>(path, "parallel unstructured grid (.pvtu)", progress,
                                                                {0.0, 0.1 * read_end, "reading pieces"});
    const int count = reader->GetNumberOfPieces();
    std::vector<vtkSmartPointer<vtkUnstructuredGrid>> pieces;
    vtkNew<ErrorCatcher> errors;
    reader->AddObserver(vtkCommand::ErrorEvent, errors);
    reader->AddObserver(vtkCommand::WarningEvent, errors);  // an unreadable piece is only a warning
    for (int i = 0; i < count; ++i) {
      const ProgressSpan piece{(0.1 + 0.7 * i / count) * read_end, (0.1 + 0.7 * (i + 1) / count) * read_end, "reading pieces"};
      update_with_progress(reader, progress, piece, path, [&] { reader->UpdatePiece(i, count, 0); });
      if (!errors->message.empty() || !reported_vtk_error().empty())
        fail_read(path, "VTK could not read piece " + std::to_string(i), *errors);
      pieces.push_back(vtkSmartPointer<vtkUnstructuredGrid>::New());
      pieces.back()->DeepCopy(reader->GetOutput());
    }
    std::vector<vtkUnstructuredGrid*> raw;
    for (auto& p : pieces) raw.push_back(p);
    return merge_pieces(path, raw, progress, {0.8 * read_end, read_end, "merging pieces"});
  }
  GridSource source;
  const ProgressSpan reading{0.0, read_end, "reading"};
  if (ext == ".vtu") source.grid = run_xml_reader<vtkXMLUnstructuredGridReader>(path, "unstructured grid (.vtu)", progress, reading)->GetOutput();
  else source.grid = read_legacy(path, progress, reading);
  return source;
}

vtkSmartPointer<vtkUnstructuredGrid> tessellate(vtkUnstructuredGrid* grid, const std::string& path, uint32_t levels,
                                                const Progress& progress, double start, double end) {
  vtkNew<vtkTessellatorFilter> filter;
  filter->SetInputData(grid);
  filter->SetOutputDimension(3);
  filter->SetMaximumNumberOfSubdivisions(int(levels));
  // Any departure from linearity beyond rounding counts, so the levels alone bound the refinement:
  // an edge is halved where its true midpoint lies off the straight one by 1e-9 of the data's
  // size, or a point array's value there is off the linear one by 1e-9 of its range (VTK's
  // vtkDataSetEdgeSubdivisionCriterion; a tolerance of 0 would turn the test off).
  constexpr double kRelative = 1e-9;
  filter->SetChordError(kRelative * std::max(grid->GetLength(), 1e-300));
  for (int i = 0; i < grid->GetPointData()->GetNumberOfArrays(); ++i) {
    vtkDataArray* array = grid->GetPointData()->GetArray(i);
    if (!array) continue;
    double range[2] = {0.0, 0.0};
    array->GetRange(range, array->GetNumberOfComponents() == 1 ? 0 : -1);  // vectors: their magnitude
    filter->SetFieldCriterion(i, kRelative * std::max(range[1] - range[0], 1e-300));
  }
  filter->MergePointsOn();
  update_with_progress(filter, progress, {start, end, "tessellating higher-order cells"}, path);
  return filter->GetOutput();
}

vtkSmartPointer<vtkUnstructuredGrid> tetrahedralize(vtkUnstructuredGrid* grid, const std::string& path, const Progress& progress,
                                                    double start, double end) {
  vtkNew<vtkDataSetTriangleFilter> filter;
  filter->TetrahedraOnlyOn();
  filter->SetInputData(grid);
  update_with_progress(filter, progress, {start, end, "splitting cells into tetrahedra"}, path);
  return filter->GetOutput();
}

}  // namespace prismoid::io::detail
