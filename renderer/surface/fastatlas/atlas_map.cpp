#include "renderer/surface/fastatlas/atlas_map.hpp"

#include <cmath>

namespace prismoid::fastatlas {

ChartMap chart_map(const PixelBox& box, const PlacedChart& placed, double scale, uint32_t border) {
  ChartMap m;
  m.screen_origin = {std::floor(box.x0), std::floor(box.y0)};
  // Pixel centre p + 1/2 of the box lands on texel centre x + 1/2 + p s: at scale 1 every pixel
  // centre is a texel centre (a lookup there reads one texel, unblurred), and at any scale the
  // bilinear taps of every pixel centre stay within the box, border texel included.
  m.atlas_origin = glm::dvec2(placed.x, placed.y) + glm::dvec2(0.5 * (double(border) - scale));
  m.scale = scale;
  m.turned = placed.turned;
  return m;
}

glm::dvec2 to_atlas(const ChartMap& map, const glm::dvec2& pixel) {
  const glm::dvec2 d = (pixel - map.screen_origin) * map.scale;
  return map.atlas_origin + (map.turned ? glm::dvec2(d.y, d.x) : d);
}

}  // namespace prismoid::fastatlas
