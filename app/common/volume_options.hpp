#pragma once
// The options `render` and `view` share: which dataset, what to show and how. Turns them into
// a loaded mesh and frame settings; InputError names the option or file at fault.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "app/common/cli_args.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/frame/volume_modes.hpp"
#include "renderer/volume/analytic_field.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::app {

// The field of a field:NAME[:N] or grid:NAME[:N] dataset, if that is what the command line names.
std::optional<volume::AnalyticField> field_of(const ParsedArgs& a);

// The dataset named on the command line; the embedded default when none is named.
// scalar_field: the chosen array is the transfer function's scalar rather than the extinction.
TetMesh load_scene(const ParsedArgs& a, bool scalar_field = false);

const char* quantity_name(volume::Quantity q);
// The inverse of quantity_name; InputError("--quantity") for an unknown name.
volume::Quantity quantity_of_name(const std::string& name);
// The volume mode --mode names (the table's default for the quantity without it); InputError
// naming every mode for a name that is none.
const frame::VolumeMode& volume_mode_from(const ParsedArgs& a, volume::Quantity quantity);

// The transfer function the color options describe, over the data's scalar range unless given.
volume::TransferFunction transfer_from(const ParsedArgs& a, const TetMesh& mesh);

extern const std::vector<std::string> kVolumeOptions;

struct VolumeChoice {
  TetMesh mesh;
  const frame::VolumeMode* mode = nullptr;  // a row of frame::volume_mode_table()
  volume::Quantity quantity = volume::Quantity::Transmittance;
  frame::FrameSettings settings;
  // --volume-backend auto: settings.backend is decided on the device (resolve_auto_backend).
  bool backend_auto = false;
};

// What loads the dataset a command line names (load_scene by default; the bench passes one that
// keeps each dataset it loaded, so its configurations do not read the same file again).
using SceneLoader = std::function<TetMesh(const ParsedArgs& a, bool scalar_field)>;

// Parses the volume options, loads the data and builds the frame settings.
VolumeChoice volume_choice(const ParsedArgs& a, const SceneLoader& load = load_scene);

}  // namespace prismoid::app
