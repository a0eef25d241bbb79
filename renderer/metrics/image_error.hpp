#pragma once
// How far an image is from its reference: the numbers the viewer's compare mode prints and the
// bench records. Images are float channels, row-major, the same layout for both. Non-finite
// values are counted separately and never averaged in, so a NaN shows up as a count rather
// than as a NaN statistic.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace prismoid::reference {

struct ImageError {
  size_t values = 0;        // channels compared (finite in both images)
  size_t non_finite = 0;    // channels where either image is NaN or infinite
  double rmse = 0.0;        // root mean square of the differences
  double max_abs = 0.0;     // largest absolute difference
  size_t max_index = 0;     // where (channel index) the largest difference is
  double mean_abs = 0.0;
  double psnr_db = 0.0;     // 20 log10(peak / rmse); +infinity when rmse is 0
};

// `peak` is the reference's signal range for the PSNR (1 for colours and transmittance; for
// optical depth the caller passes the reference's largest value). `channels` lets callers
// skip channels: only the first `compared` of every `channels` values are compared (e.g. RGB of
// RGBA with channels 4, compared 3).
ImageError image_error(std::span<const float> test, std::span<const float> reference, double peak, size_t channels = 1,
                       size_t compared = 1);

// Mean structural similarity (Wang, Bovik, Sheikh & Simoncelli 2004, "Image quality assessment:
// from error visibility to structural similarity"): luminance, contrast and structure compared
// in an 11x11 Gaussian window (sigma 1.5; smaller images use the largest odd window that fits)
// around every pixel whose window lies inside the image, with C1 = (0.01 peak)^2 and
// C2 = (0.03 peak)^2; the mean over those pixels and the compared channels. 1 for identical
// images, lower as structure differs. NaN when a compared value is not finite (image_error
// counts those).
double ssim(std::span<const float> test, std::span<const float> reference, uint32_t width, uint32_t height, double peak,
            size_t channels = 1, size_t compared = 1);

// A heat map of per-pixel error for display: for each pixel, the largest absolute difference
// over its compared channels, mapped through a perceptually ordered black-red-yellow-white ramp
// with `scale` at white (scale <= 0: the image's own maximum). Non-finite pixels are magenta.
// Returns linear RGBA, 4 floats per pixel.
std::vector<float> error_heat_map(std::span<const float> test, std::span<const float> reference, size_t channels,
                                  size_t compared, double scale);

}  // namespace prismoid::reference
