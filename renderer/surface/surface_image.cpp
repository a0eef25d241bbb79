#include "renderer/surface/surface_image.hpp"

#include <cstddef>

namespace prismoid::surface {

std::vector<float> SurfaceImage::rgb() const {
  std::vector<float> out;
  out.reserve(size_t(width) * height * 3);
  for (size_t i = 0; i + 4 <= rgba.size(); i += 4) out.insert(out.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
  return out;
}

}  // namespace prismoid::surface
