#include "app/common/frame_image.hpp"

#include <filesystem>

namespace prismoid::app {

io::FloatImage frame_image(const frame::OffscreenFrame& result, const std::string& path, bool color) {
  io::FloatImage image;
  image.width = result.width;
  image.height = result.height;
  const auto extension = std::filesystem::path(path).extension();
  const bool pfm = extension == ".pfm" || extension == ".PFM";
  if (pfm && !color) {  // a scalar per pixel (optical depth, transmittance, the distance to an isosurface)
    image.channels = 1;
    image.pixels = result.quantity;
  } else if (pfm) {  // colour PFM: the linear colour over the background, RGB
    image.channels = 3;
    image.pixels.resize(result.display.size() / 4 * 3);
    for (size_t i = 0; i < result.display.size() / 4; ++i)
      for (size_t k = 0; k < 3; ++k) image.pixels[3 * i + k] = result.display[4 * i + k];
  } else {
    image.channels = 4;
    image.pixels = result.display;
  }
  return image;
}

}  // namespace prismoid::app
