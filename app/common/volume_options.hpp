#pragma once
// The options `render` and `view` share: which dataset, what to show and how. Turns them into
// a loaded mesh and frame settings; InputError names the option or file at fault.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

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

// Colour's look when the command line names none (the user guide states these rules):
// - the colour map is viridis (perceptually ordered, readable on a dark background);
// - the opacity is 0 up to the field's median (at least 0.2, at most 0.8 of the range), rising
//   linearly to 1 at the top of the range, so the bulk of the data (often empty space or a
//   smooth background) stays clear and the structure above it shows;
// - the extinction at opacity 1 (--density-scale) is kDiagonalOpticalDepth over the diagonal of
//   the data's bounds, so that a dataset's look does not depend on its units: a ray across it
//   through opacity 1 would have optical depth 35; through the typical opacity of the visible
//   part (about 0.3) about 10, opaque enough to hide what lies behind the densest structure,
//   clear enough to see into the rest;
// - the background is almost black, which emission reads best against.
inline constexpr const char* kDefaultColourMap = "viridis";
inline constexpr double kLowestHidden = 0.2, kMostHidden = 0.8;
inline constexpr double kDiagonalOpticalDepth = 35.0;
inline constexpr glm::vec3 kDefaultColourBackground{0.01f, 0.01f, 0.015f};
struct ColourLook {
  double opacity_from = kLowestHidden;  // normalized scalar where the opacity starts to rise
  double density_scale = 1.0;
};
ColourLook default_colour_look(const TetMesh& mesh);

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

// --depth-limit FILE.pfm: one value per pixel of the frame, the depth along the viewing axis
// where the ray ends (opaque geometry), +inf where nothing is; row 0 at the top as the image's.
// InputError naming the file for another size, more channels or a depth that is not positive.
std::shared_ptr<const std::vector<float>> read_depth_limit(const std::string& path, VkExtent2D size);

}  // namespace prismoid::app
