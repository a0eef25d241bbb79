#pragma once
// Where a chart's screen pixels land in the atlas (FastAtlas, section 5.2 and appendix A): the
// chart is parametrized by its own screen projection, so its map into the atlas is the packer's
// scale and a translation, with the axes swapped for a box the packer turned. Every texel then
// stands for 1/s pixels, the same over the whole image: the stretch between screen and atlas is
// 1/s everywhere (Sander's L2 and L-infinity alike).
#include <cstdint>

#include <glm/vec2.hpp>

#include "renderer/surface/fastatlas/atlas_packing.hpp"
#include "renderer/surface/fastatlas/charts.hpp"

namespace prismoid::fastatlas {

struct ChartMap {
  glm::dvec2 screen_origin{0.0};  // the chart's box corner in pixels (whole pixels: what the packer sized)
  glm::dvec2 atlas_origin{0.0};   // where that corner lands, in texels: the placed box's corner + (border - scale) / 2
  double scale = 1.0;             // texels per pixel
  bool turned = false;            // screen x runs along atlas y
};

// `box`: the chart's screen box (chart_boxes); `placed`: its place (pack_atlas).
ChartMap chart_map(const PixelBox& box, const PlacedChart& placed, double scale, uint32_t border);

// A screen point of the chart (pixels, y down) to the atlas (texels).
glm::dvec2 to_atlas(const ChartMap& map, const glm::dvec2& pixel);

}  // namespace prismoid::fastatlas
