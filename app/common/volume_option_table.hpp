#pragma once
// The volume options as one table (issue "One renderer for every front end"), beside the mode
// tables: each option of a volume that `render`, `view`, `info --plan` and the bench take is a row
// here, with the form of its value, its help and the values the bench sweeps. The verbs parse
// from it (volume_value_options, volume_flag_options), `render --help` and `view --help` list it
// (volume_options_help), the bench's sweeps take their values from it (volume_option_sweep).
// volume_choice (volume_options.hpp) reads the parsed values into a mesh and FrameSettings.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace prismoid::app {

// Where an option belongs in the help (and what it applies to).
enum class VolumeOptionGroup {
  Mode,     // --mode and --volume-backend: their help is the mode and backend tables
  Quantity,
  Mesh,     // the mesh backend's workgroups
  Data,     // which array, how dense
  March,    // the marching modes
  Color,    // --quantity color
  Tetgen,   // a closed surface filled with tetrahedra
  Image,    // image volumes
  Vdb,      // OpenVDB grids
  Exodus,   // Exodus II files
  Time,     // time series and Exodus II steps
};

struct VolumeOption {
  std::string_view name;   // the setting's key (scene/setting_names.hpp); the CLI spells it --NAME
  std::string_view value;  // its value's form in the help ("N", "LO,HI"); empty: a flag
  std::string_view help;
  VolumeOptionGroup group;
  // The values the bench sweeps beside the default (the first alone with --quick); none: not swept.
  std::vector<std::string_view> sweep = {};
  bool flag() const { return value.empty(); }
};

// Every volume option, in the order the help lists them.
const std::vector<VolumeOption>& volume_option_table();
// The row of that name; nullptr for none.
const VolumeOption* find_volume_option(std::string_view name);
// The names of the options that take a value, and of the flags.
std::vector<std::string> volume_value_options();
std::vector<std::string> volume_flag_options();
// The help lines of one group: "  --NAME VALUE" and the help from column `text_column`, wrapped.
std::string volume_options_help(VolumeOptionGroup group, size_t text_column);
// "--a, --b, --c" of the groups' options, for a help that refers to render's.
std::string volume_option_list(const std::vector<VolumeOptionGroup>& groups);
// The values the bench sweeps of an option (the first only, quick).
std::vector<std::string> volume_option_sweep(std::string_view name, bool quick);

}  // namespace prismoid::app
