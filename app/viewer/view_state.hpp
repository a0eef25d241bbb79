#pragma once
// What the window shows, apart from the camera: the datasets, which one is drawn, the mode and
// its settings, and the UI's own switches. Plain data and free functions; the panels and the
// script edit it, the frame loop reads it. Several datasets and the compare setting are
// already here so split view and background loading can be added without reshaping it.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/common/dataset_loader.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/volume/analytic_field.hpp"
#include "scene/bounds.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::app {

// One loaded dataset and what the UI needs to know about it.
struct Dataset {
  std::string name;
  std::shared_ptr<const TetMesh> mesh;
  std::optional<volume::AnalyticField> field;  // field:NAME datasets: what interval-march samples
  Bounds bounds;
  bool has_scalars = false;                    // colour needs a scalar field
  double scalar_lo = 0.0, scalar_hi = 1.0;     // the data's range (hi > lo)
  bool visible = true;                         // drawn as part of the scene
  // A time series or an Exodus file with steps: how it was loaded (another step is the same
  // request at another --time-step), the steps' times, and the step shown. No times: not
  // time-dependent.
  std::optional<LoadRequest> source;
  std::vector<double> times;
  uint32_t step = 0;
};

// Builds the description of a loaded mesh. Touches no global state, so a loader thread may
// call it and hand the result to the window.
Dataset make_dataset(TetMesh mesh, std::optional<volume::AnalyticField> field = std::nullopt);
// Records that `d` was loaded by `request`: where it is a time series or an Exodus file with
// steps, its steps' times and the step shown (InputError as reading the series).
void attach_time(Dataset& d, const LoadRequest& request);

// How the view compares modes: not at all, A | B side by side on one camera (A the current
// mode, B the compare mode below), or the current mode's error against the CPU reference as a
// heat map (app/viewer/compare.hpp).
enum class CompareMode { Off, Split, Difference };

struct ViewState {
  std::vector<Dataset> datasets;
  size_t active = 0;  // the dataset whose arrays and range the transfer function uses
  // What is drawn: the visible datasets as one (dataset_list.hpp keeps it current). Empty until
  // first built; drawn() then falls back to the active dataset.
  Dataset scene;
  CompareMode compare = CompareMode::Off;
  std::string mode{frame::find_volume_mode(frame::Ordering::MeshOrder, false)->name};  // a GPU mode of the volume mode table
  frame::FrameSettings settings;
  // Split view's B: its mode, and its settings (its own ordering, quantity and pre-integration
  // size; the rest follows A each frame: compare_frame_settings). Empty mode: not chosen yet.
  std::string compare_mode;
  frame::FrameSettings compare_settings;
  // Split view's B at another time step of the active dataset (its mesh, loaded as that step):
  // A | B then compare two steps in one mode (or two modes at two steps). None: B draws the step
  // A shows.
  std::optional<uint32_t> compare_step;
  std::shared_ptr<const TetMesh> compare_step_mesh;
  std::string tf_preset = "cool-to-warm";
  // Stepping through time: whether the transfer function's range follows each step's data range.
  // Off by default, as ParaView keeps the range while its time moves: colours then mean the same
  // value at every step, and a quantity that grows looks like it grows.
  bool range_per_step = false;
  bool show_ui = true;
  const Dataset& dataset() const { return datasets.at(active); }
  const Dataset& drawn() const { return scene.mesh ? scene : dataset(); }
};

// The GPU modes of the volume mode table the dataset can use (set_mode and set_quantity ask this of
// the drawn scene): the march modes only for datasets with a field.
std::vector<std::string> modes_for(const Dataset& dataset);
// The quantities a mode can show for the dataset.
std::vector<volume::Quantity> quantities_for(const Dataset& dataset, const std::string& mode);

// Each returns an empty string when applied, else why not (the state is then unchanged).
std::string set_mode(ViewState& state, const std::string& mode);
std::string set_quantity(ViewState& state, volume::Quantity quantity);
std::string set_preset(ViewState& state, const std::string& preset_name);
// Whether shared vertices (tetlets) can be used now: they fix the draw order, so not with an
// order-dependent quantity in a sorted mode. Empty when they can.
std::string shared_vertices_problem(const ViewState& state);

}  // namespace prismoid::app
