#include "app/common/volume_option_table.hpp"

#include <algorithm>
#include <sstream>

#include "app/common/cli_args.hpp"

namespace prismoid::app {

namespace {

using G = VolumeOptionGroup;

// Help lines wrap here.
constexpr size_t kWidth = 101;

}  // namespace

const std::vector<VolumeOption>& volume_option_table() {
  static const std::vector<VolumeOption> table = {
      {"mode", "MODE", "", G::Mode},
      {"volume-backend", "B", "", G::Mode},
      {"quantity", "Q",
       "optical-depth | transmittance | color | isosurface (default transmittance). color: emission-absorption of a scalar field "
       "through a transfer function; isosurface: the nearest point where the field reaches --isovalue, shaded with a headlight (the "
       "modes that sample the field, field: datasets); the .pfm quantity is the distance from the eye to it (0: no hit)",
       G::Quantity},
      {"tetlet-size", "N", "cells per mesh workgroup: 1 (the paper's one cell per workgroup), 4, 8 or 16 (default 16)", G::Mesh,
       {"1", "4", "8"}},
      {"shared-vertices", "",
       "tetlets: group neighbouring cells so a workgroup loads their shared points once (order-independent quantities, or a mode "
       "in mesh order)",
       G::Mesh},
      {"array", "NAME",
       "array giving the extinction, or for color the transfer function's scalar (vectors by magnitude): a cell array is constant "
       "per cell, a point array linear in each cell; default sigma = 1 (the default dataset: its density)",
       G::Data},
      {"component", "C", "of a vector --array: 0, 1, 2... or x, y, z (default: magnitude)", G::Data},
      {"subdivision", "N",
       "higher-order cells (quadratic, Lagrange, Bezier): 0 splits them through their nodes (default); N (at most 5) "
       "tessellates them with VTK's vtkTessellatorFilter, each edge halved up to N times where the cell's shape or a point "
       "array is not linear along it",
       G::Data},
      {"density-scale", "S",
       "multiplies the extinction (default 1); for color, the extinction at opacity 1 (default 35 / the diagonal of the data's "
       "bounds: the same look in any units)",
       G::Data},
      {"march-step", "S",
       "longest step in world units: each interval is marched in equal steps of at most S (midpoint rule) (default: 1/100 of the "
       "bounds' diagonal)",
       G::March},
      {"isovalue", "V", "the isosurface's level (--quantity isosurface only; default 0.5)", G::March},
      {"tf", "PRESET|FILE",
       "transfer function: viridis, cool-to-warm, grayscale, black-body, or a ParaView colour-map JSON file (opacity from its "
       "\"Points\", else a ramp); default: viridis, opacity 0 up to the field's median (0.2-0.8 of the range), then rising to 1",
       G::Color},
      {"tf-range", "LO,HI", "scalar values mapped to the ends of the transfer function (default: data range)", G::Color},
      {"preintegration-size", "N",
       "0: integrate each segment exactly in the shader (default); N in 2..256: look segments up in an N^3 pre-integrated table "
       "(faster, approximate)",
       G::Color, {"16", "64", "256"}},
      {"background", "R,G,B", "linear colour behind the volume (default 0.01,0.01,0.015)", G::Color},
      {"tetgen-quality", "Q", "radius-edge bound, TetGen -q (default 1.414; smaller: rounder, more cells)", G::Tetgen},
      {"tetgen-max-volume", "V", "largest cell volume, TetGen -a (default: none)", G::Tetgen},
      {"tetgen-cells", "N", "about N tetrahedra (within 15%): TetGen -a chosen for it, 1-3 runs", G::Tetgen},
      {"fill-holes", "", "close an open surface first (VTK's vtkFillHolesFilter)", G::Tetgen},
      {"remesh", "H",
       "replace the surface by its OpenVDB level set's zero crossing at voxel size H (closed, no self-intersections; detail below "
       "H is lost)",
       G::Tetgen},
      {"subsample", "K", "keep 1 voxel in K per axis (images over 50 million cells need it)", G::Image},
      {"grid", "NAME", "the float grid to open (default: the file's first; --subsample applies)", G::Vdb},
      {"blocks", "LIST",
       "the blocks to draw, comma-separated: an Exodus II file's element blocks by id or name (default: those that hold 3D "
       "cells), a .vtm's blocks by index or name (default: its unstructured grids); `prismoid info` lists them",
       G::Exodus},
      {"time-step", "N", "the step to draw, 0 the first (default 0; `prismoid info` lists the steps and their times)", G::Time},
      {"time", "T", "the step at time T: the last at or before it (as ParaView snaps a time to a step)", G::Time},
  };
  return table;
}

const VolumeOption* find_volume_option(std::string_view name) {
  for (const VolumeOption& o : volume_option_table())
    if (o.name == name) return &o;
  return nullptr;
}

std::vector<std::string> volume_value_options() {
  std::vector<std::string> names;
  for (const VolumeOption& o : volume_option_table())
    if (!o.flag()) names.emplace_back(o.name);
  return names;
}

std::vector<std::string> volume_flag_options() {
  std::vector<std::string> names;
  for (const VolumeOption& o : volume_option_table())
    if (o.flag()) names.emplace_back(o.name);
  return names;
}

std::string volume_options_help(VolumeOptionGroup group, size_t text_column) {
  std::ostringstream out;
  for (const VolumeOption& o : volume_option_table()) {
    if (o.group != group) continue;
    std::string line = std::string("  --").append(o.name);
    if (!o.flag()) line.append(" ").append(o.value);
    // A name that reaches the text's column has its text two spaces after it.
    line.append(line.size() + 2 <= text_column ? text_column - line.size() : 2, ' ');
    out << wrap_words(std::move(line), o.help, text_column, kWidth);
  }
  return out.str();
}

std::string volume_option_list(const std::vector<VolumeOptionGroup>& groups) {
  std::string list;
  for (const VolumeOption& o : volume_option_table())
    if (std::find(groups.begin(), groups.end(), o.group) != groups.end()) list.append(list.empty() ? "--" : ", --").append(o.name);
  return list;
}

std::vector<std::string> volume_option_sweep(std::string_view name, bool quick) {
  const VolumeOption* o = find_volume_option(name);
  std::vector<std::string> values;
  if (!o) return values;
  for (const std::string_view v : o->sweep) {
    values.emplace_back(v);
    if (quick) break;
  }
  return values;
}

}  // namespace prismoid::app
