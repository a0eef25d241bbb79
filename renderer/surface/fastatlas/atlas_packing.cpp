#include "renderer/surface/fastatlas/atlas_packing.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace prismoid::fastatlas {

namespace {

// Rows run left to right, then two right to left, repeated (section 4.3).
bool mirrored_row(uint64_t row) { return row % 3 != 0; }

// A side at `scale`: rounded up (so a chart never gets fewer texels than its pixels at that
// scale), at least one texel, plus the border.
uint32_t scaled(uint32_t side, double scale, uint32_t border) {
  const double s = std::ceil(double(side) * scale);
  return uint32_t(std::max(1.0, s)) + border;
}

}  // namespace

std::vector<double> candidate_scales(const PackingOptions& options) {
  std::vector<double> scales(options.candidates);
  const double ratio = options.smallest_scale / options.largest_scale;
  for (uint32_t k = 0; k < options.candidates; ++k) {
    const double s = options.candidates == 1 ? options.largest_scale
                                             : options.largest_scale * std::pow(ratio, double(k) / double(options.candidates - 1));
    // A multiple of 2^-16, so that ceil(side * s) is exact in double here and in integers on the
    // GPU (pack.comp): both sides round every box alike.
    scales[k] = std::max(1.0, std::round(s * 65536.0)) / 65536.0;
  }
  return scales;
}

std::vector<uint32_t> packing_order(const std::vector<ChartBox>& boxes) {
  std::vector<uint32_t> order(boxes.size());
  std::iota(order.begin(), order.end(), 0u);
  auto tall = [&](uint32_t i) { return std::max(boxes[i].width, boxes[i].height); };
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (tall(a) != tall(b)) return tall(a) > tall(b);
    if (boxes[a].root != boxes[b].root) return boxes[a].root < boxes[b].root;
    return a < b;
  });
  return order;
}

AtlasPacking pack_at_scale(const std::vector<ChartBox>& boxes, const std::vector<uint32_t>& order, double scale,
                           const PackingOptions& options) {
  const uint32_t W = options.atlas_width, H = options.atlas_height;
  AtlasPacking p;
  p.scale = scale;
  p.charts.resize(boxes.size());
  if (boxes.empty()) {
    p.fits = true;
    return p;
  }
  // Sizes at this scale, turned so that height >= width.
  uint32_t widest = 0;
  for (uint32_t i : order) {
    const ChartBox& b = boxes[i];
    PlacedChart& c = p.charts[i];
    c.turned = b.width > b.height;
    c.width = scaled(c.turned ? b.height : b.width, scale, options.border);
    c.height = scaled(c.turned ? b.width : b.height, scale, options.border);
    widest = std::max(widest, c.width);
  }
  if (widest > W) return p;  // a box wider than the atlas: no fold places it
  const uint64_t capacity = std::max<uint64_t>(1, W - widest);
  // Fold: the exclusive prefix sum of the widths cut into rows of `capacity`.
  std::vector<uint32_t> front(W, 0);  // per column, the lowest texel row taken so far
  uint64_t prefix = 0;
  size_t first = 0;
  while (first < order.size()) {
    const uint64_t row = prefix / capacity;
    // This row's boxes: those whose prefix sum starts in it (consecutive in the order).
    size_t end = first;
    uint64_t sum = prefix;
    while (end < order.size() && sum / capacity == row) sum += p.charts[order[end++]].width;
    // Push up: each box rises to the front line over its columns; boxes of one row do not share
    // columns, so their order within the row does not matter.
    uint64_t at = prefix;
    for (size_t k = first; k < end; ++k) {
      PlacedChart& c = p.charts[order[k]];
      const uint32_t x = uint32_t(at % capacity);
      at += c.width;
      c.x = mirrored_row(row) ? W - x - c.width : x;
      c.y = *std::max_element(front.begin() + c.x, front.begin() + c.x + c.width);
    }
    for (size_t k = first; k < end; ++k) {
      const PlacedChart& c = p.charts[order[k]];
      std::fill(front.begin() + c.x, front.begin() + c.x + c.width, c.y + c.height);
      p.height_used = std::max(p.height_used, c.y + c.height);
    }
    prefix = sum;
    first = end;
  }
  p.fits = p.height_used <= H;
  return p;
}

AtlasPacking pack_atlas(const std::vector<ChartBox>& boxes, const PackingOptions& options) {
  if (options.atlas_width == 0 || (options.atlas_width & (options.atlas_width - 1)) != 0)
    throw std::invalid_argument("FastAtlas packing: the atlas width must be a power of two");
  if (options.candidates == 0 || !(options.largest_scale > 0.0) || !(options.smallest_scale > 0.0) ||
      options.smallest_scale > options.largest_scale)
    throw std::invalid_argument("FastAtlas packing: candidates must be > 0 and 0 < smallest scale <= largest scale");
  for (const ChartBox& b : boxes)
    if (b.width == 0 || b.height == 0) throw std::invalid_argument("FastAtlas packing: a chart box of size 0");
  const std::vector<uint32_t> order = packing_order(boxes);
  const std::vector<double> scales = candidate_scales(options);
  // Every candidate is packed (on the GPU, in parallel); the largest that fits wins.
  for (uint32_t k = 0; k < scales.size(); ++k) {
    AtlasPacking p = pack_at_scale(boxes, order, scales[k], options);
    if (p.fits) {
      p.candidate = k;
      return p;
    }
  }
  AtlasPacking none;
  none.candidate = uint32_t(scales.size());
  return none;
}

}  // namespace prismoid::fastatlas
