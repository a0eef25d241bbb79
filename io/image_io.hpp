#pragma once
// Image files: PNG for people (8-bit sRGB), PFM for numbers (raw float32).
#include <cstdint>
#include <string>
#include <vector>

namespace prismoid::io {

// A float image, row-major, row 0 at the top, `channels` interleaved values per pixel.
struct FloatImage {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t channels = 1;  // 1 or 3 (PFM); PNG also accepts 4
  std::vector<float> pixels;
  float at(uint32_t x, uint32_t y, uint32_t c = 0) const { return pixels[(size_t(y) * width + x) * channels + c]; }
};

// The writers write `path` itself and remove it again when the write fails; putting a file in
// place whole (a temporary beside it, renamed) is the caller's: app/common/output_files.hpp.
// Writes linear colour in [0, 1] as 8-bit sRGB PNG (1, 3 or 4 channels). Throws InputError
// naming the path when it cannot be written.
void write_png(const std::string& path, const FloatImage& image);
// Portable float map: "Pf" (1 channel) or "PF" (3 channels), little-endian, stored with
// the bottom row first as the format specifies.
void write_pfm(const std::string& path, const FloatImage& image);
FloatImage read_pfm(const std::string& path);

// Writes through the format its extension names (.png or .pfm); InputError otherwise.
void write_image(const std::string& path, const FloatImage& image);
bool is_supported_image_path(const std::string& path);

}  // namespace prismoid::io
