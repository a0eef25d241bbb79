#pragma once
// The image file a rendered frame becomes, shared by `prismoid render` and the window's
// "render this view at N x M": PNG gets the display colour, PFM the numbers (the quantity, or
// for colour the linear RGB over the background).
#include <string>

#include "io/image_io.hpp"
#include "renderer/frame/frame_renderer.hpp"

namespace prismoid::app {

// `color`: the quantity is colour (order-dependent RGB) rather than a scalar per pixel.
io::FloatImage frame_image(const frame::OffscreenFrame& frame, const std::string& path, bool color);

}  // namespace prismoid::app
