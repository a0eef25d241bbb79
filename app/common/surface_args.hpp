#pragma once
// The command line's surface scenes, shared by the surface render modes (path-reference,
// forward): which scene FILE names and the camera the options make of the scene's own.
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/common/cli_args.hpp"
#include "renderer/volume/transfer_function.hpp"
#include "scene/surface_mesh.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::app {

// Colour from a data array of a surface file, as a scientist colours by a field in ParaView:
// --array NAME (a point array colours vertices, interpolated across triangles; a cell array
// colours whole triangles), --component x|y|z|N|magnitude (vectors default to the magnitude),
// --tf PRESET|FILE (default cool-to-warm), --tf-range LO,HI (default: the array's range).
// The colour multiplies the material's diffuse albedo.
struct SurfaceArrayColoring {
  std::string array;   // empty: no colouring
  int component = -1;  // -1: magnitude (or the only component)
  volume::TransferFunction transfer;
  std::optional<std::pair<double, double>> range;
};
SurfaceArrayColoring array_coloring_from(const ParsedArgs& a);
inline const std::vector<std::string> kSurfaceColorOptions = {"array", "component", "tf", "tf-range"};
inline const std::vector<std::string> kSurfaceRefineOption = {"max-triangle-pixels"};
// `options` with the colouring options and --max-triangle-pixels added: the options every verb
// that loads a surface scene takes.
inline std::vector<std::string> with_surface_color(std::vector<std::string> options) {
  options.insert(options.end(), kSurfaceColorOptions.begin(), kSurfaceColorOptions.end());
  options.insert(options.end(), kSurfaceRefineOption.begin(), kSurfaceRefineOption.end());
  return options;
}
// Colours scene.meshes[0] (the surface's mesh) from `surface`'s array; nothing without
// coloring.array. InputError naming the file and listing its arrays for an unknown name, or a
// non-finite value.
void color_by_array(SurfaceScene& scene, const SurfaceMesh& surface, const SurfaceArrayColoring& coloring);

// cornell-box, furnace:A[:LE] or a surface file (.vtp .stl .obj .ply .off), coloured by
// --array when given; InputError for anything else, naming `mode`.
SurfaceScene surface_scene_from(const ParsedArgs& a, const std::string& mode);

// --max-triangle-pixels P: the scene's large triangles split until none spans more than P pixels
// of a width x height image from `camera` (refine_large_triangles, as the meshlet shading
// atlas's paper prepares its scenes); the scene as it is without the option.
SurfaceScene refined_for_view(const ParsedArgs& a, SurfaceScene scene, const Camera& camera, uint32_t width, uint32_t height);

// The scene's own camera, with each camera option given replacing its part (the near plane from
// the new eye where --eye or --target is given without --near: near_plane_for); validated.
Camera surface_camera(const ParsedArgs& a, const SurfaceScene& scene);

}  // namespace prismoid::app
