#include "renderer/surface/fastatlas/atlas_map.hpp"

#include <cmath>

namespace prismoid::fastatlas {

ChartMap chart_map(const PixelBox& box, const PlacedChart& placed, double scale, uint32_t border) {
  ChartMap m;
  m.screen_origin = {std::floor(box.x0), std::floor(box.y0)};
  // The border's texels shared out on both sides, so bilinear taps at the chart's edge stay in
  // its own box.
  m.atlas_origin = glm::dvec2(placed.x, placed.y) + glm::dvec2(0.5 * border);
  m.scale = scale;
  m.turned = placed.turned;
  return m;
}

glm::dvec2 to_atlas(const ChartMap& map, const glm::dvec2& pixel) {
  const glm::dvec2 d = (pixel - map.screen_origin) * map.scale;
  return map.atlas_origin + (map.turned ? glm::dvec2(d.y, d.x) : d);
}

}  // namespace prismoid::fastatlas
