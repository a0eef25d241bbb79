#pragma once
// FastAtlas's packing of chart boxes into one atlas per frame (Real-Time Compact Atlases for
// Texture Space Shading, section 4), as plain data: the rule the GPU packer follows and the CPU
// twin its tests compare against.
//
// Each chart's box is its screen-space bounding box in pixels (a texel per pixel at scale 1).
// All charts are scaled by one factor, the largest of a fixed set of candidates at which every
// box fits, so the texel-to-pixel ratio stays the same over the whole image (section 4.2):
//  1. Order (section 4.1): each box is turned so that it is at least as tall as wide, then the
//     boxes are sorted by height, tallest first, ties by the chart's root (its lowest triangle
//     index). The order depends only on the boxes, not on the order they arrive in, so the same
//     frame gives the same atlas bit for bit.
//  2. Fold (section 4.3): at a candidate scale the boxes' widths (rounded up, plus the border) are
//     laid along one line and cut into rows by an exclusive prefix sum: box i goes to row
//     floor(P_i / C), at x = P_i mod C, with the row capacity C = W - (the widest box). A box
//     starting before C therefore ends by W: no row overflows. (The paper lets the last box of a
//     row overflow by o and rescales by W / (W + o); a fixed capacity keeps every candidate's
//     rows exact in integers, at the cost of up to one box width per row.) Rows run left to
//     right, then two right to left, repeated, as the paper's atlases of a few large charts want.
//  3. Push up: rows are placed in order; each box rises to the highest free line over the
//     columns it covers (the front line), then raises that line by its height.
//  4. A candidate fits when the highest box ends within the atlas's height; the chosen scale is
//     the largest candidate that fits.
#include <cstdint>
#include <vector>

namespace prismoid::fastatlas {

struct ChartBox {
  uint32_t width = 0, height = 0;  // pixels at scale 1 (at least 1 each)
  uint32_t root = 0;               // the chart's lowest triangle index: the tie-break
};

struct PackingOptions {
  uint32_t atlas_width = 8192, atlas_height = 8192;
  uint32_t border = 1;         // texels added to each side's size for bilinear borders
  uint32_t candidates = 64;    // scales tried, largest first
  double largest_scale = 1.0;  // the texel-to-pixel target (shading-rate factor SF; 1: one texel per pixel)
  double smallest_scale = 1.0 / 64.0;
};

struct PlacedChart {
  uint32_t x = 0, y = 0;          // the box's corner in the atlas, texels
  uint32_t width = 0, height = 0; // its size in the atlas at the chosen scale, border included
  bool turned = false;            // turned by 90 degrees (the chart's x runs along the atlas's y)
};

struct AtlasPacking {
  bool fits = false;              // some candidate fits (else `charts` is empty)
  uint32_t candidate = 0;         // the chosen candidate's index (0: the largest scale)
  double scale = 0.0;             // its scale
  uint32_t height_used = 0;       // texels from the atlas's top the boxes reach
  std::vector<PlacedChart> charts;  // per input box, in the input's order
};

// The candidates' scales, largest first: geometric from largest_scale to smallest_scale, each
// rounded to a multiple of 2^-16 (the GPU packer's fixed point).
std::vector<double> candidate_scales(const PackingOptions& options);

// The packing order: indices into `boxes`, tallest (turned) first, ties by root, then by index.
std::vector<uint32_t> packing_order(const std::vector<ChartBox>& boxes);

// The layout at one scale (whether it fits, and where each box goes); `order` from packing_order.
AtlasPacking pack_at_scale(const std::vector<ChartBox>& boxes, const std::vector<uint32_t>& order, double scale,
                           const PackingOptions& options);

// The largest candidate scale at which every box fits, and the layout there. Throws
// std::invalid_argument for an atlas width that is not a power of two or a box of size 0.
AtlasPacking pack_atlas(const std::vector<ChartBox>& boxes, const PackingOptions& options);

}  // namespace prismoid::fastatlas
