#pragma once
// A camera as one line of `prismoid render` options, so a view found in the window can be
// re-rendered from the command line, and a line pasted back restores it.
#include <string>

#include "scene/bounds.hpp"
#include "scene/camera.hpp"

namespace prismoid::app {

// "--eye x,y,z --target x,y,z --up x,y,z --fovy D --near N", every number with 17 significant
// digits (a double survives the round trip exactly).
std::string camera_line(const Camera& camera);

// Parses a line of camera options through the command line's own parser (cli_args), framing
// `bounds` for the options it leaves out. Throws InputError naming the bad option.
Camera camera_from_line(const std::string& line, const Bounds& bounds);

}  // namespace prismoid::app
