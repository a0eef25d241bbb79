#pragma once
// LDR-FLIP: a perceptual difference between two colour images, from
//   P. Andersson, J. Nilsson, T. Akenine-Moller, M. Oskarsson, K. Astrom, M. D. Fairchild,
//   "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact.
//   Tech. 3(2), Article 15, 2020 (HPG 2020), https://doi.org/10.1145/3406183.
// Per pixel it says how different the two images look to an observer flipping between them,
// 0 (no visible difference) to 1 (the largest colour difference FLIP knows, green against blue).
// Two pipelines meet per pixel: a colour pipeline (the images filtered by the eye's contrast
// sensitivity in an opponent colour space, then a HyAB distance in Hunt-adjusted L*a*b*) and a
// feature pipeline (edges and points of the luminance that one image has and the other lacks),
// combined as colour^(1 - feature). flip.cpp cites the paper for every constant.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace prismoid::reference {

struct FlipResult {
  double mean = 0;        // mean of `map` over the pixels that are finite in both images (0 when none is)
  double max = 0;         // largest value of `map` over those pixels
  std::vector<float> map;  // width x height, row-major, in [0, 1]; NaN where a pixel was not finite
  size_t non_finite = 0;   // pixels with a NaN or infinite R, G or B in either image
};

// Compares the first three channels (linear RGB, the renderer's display values) of every
// `stride` floats. The paper's input is an sRGB-encoded LDR image whose first step is decoding
// to linear RGB, so linear values enter the pipeline directly with no encode/decode round trip;
// values are clamped to [0, 1] first, as the display shows them (an sRGB swapchain or PNG
// clamps too). A pixel that is not finite in one image takes the other image's colour (black if
// neither is finite) before filtering, so it neither spreads NaN nor adds a difference to its
// neighbours; it is counted in `non_finite`, left out of mean and max, and NaN in `map`.
// `pixels_per_degree` is the observer's pixels per degree of visual angle: the paper's default
// viewer (a 0.7 m wide 3840-pixel monitor seen from 0.7 m) has 0.7 * 3840 / 0.7 * pi / 180 =
// 67.02. Larger values mean a farther observer or smaller pixels: fine detail matters less.
// Throws std::invalid_argument for an empty image, a stride under 3, a size that is not
// width x height x stride, or pixels_per_degree that is not finite and positive.
FlipResult flip(const std::vector<float>& test, const std::vector<float>& reference, uint32_t width, uint32_t height,
                uint32_t stride, double pixels_per_degree = 67.0);

}  // namespace prismoid::reference
