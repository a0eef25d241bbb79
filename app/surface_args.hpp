#pragma once
// The command line's surface scenes, shared by the surface render modes (path-reference,
// forward): which scene FILE names and the camera the options make of the scene's own.
#include <string>

#include "app/cli_args.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::app {

// cornell-box, furnace:A[:LE] or a surface file (.vtp .stl .obj .ply .off); InputError for
// anything else, naming `mode`.
SurfaceScene surface_scene_from(const ParsedArgs& a, const std::string& mode);

// The scene's own camera, with each camera option given replacing its part; validated.
Camera surface_camera(const ParsedArgs& a, Camera camera);

}  // namespace prismoid::app
