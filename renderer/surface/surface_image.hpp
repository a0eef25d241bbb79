#pragma once
// The colour a surface backend reads back after a frame: linear RGBA floats, row-major, row 0 at
// the top (alpha 1 where a surface is seen, 0 on the sky). ForwardImage and TextureSpaceImage
// add their passes' own read-backs.
#include <cstdint>
#include <vector>

namespace prismoid::surface {

struct SurfaceImage {
  uint32_t width = 0, height = 0;
  std::vector<float> rgba;
  std::vector<float> rgb() const;  // 3 floats per pixel, as PFM and image_error take them
};

}  // namespace prismoid::surface
