#include "io/image_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iomanip>
#include <fstream>
#include <sstream>

#include "io/file_write.hpp"
#include "io/path_util.hpp"
#include "scene/input_error.hpp"

#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO_FAILURE_MESSAGES
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#endif
#include <stb/stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace prismoid::io {

namespace {


uint8_t to_srgb8(float linear) {
  float v = std::clamp(std::isfinite(linear) ? linear : 0.0f, 0.0f, 1.0f);
  float s = v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
  return static_cast<uint8_t>(std::lround(s * 255.0f));
}

void check_shape(const std::string& path, const FloatImage& image) {
  if (image.width == 0 || image.height == 0) throw InputError(path, "image has no pixels");
  if (image.pixels.size() != size_t(image.width) * image.height * image.channels)
    throw InputError(path, "image data does not match its size");
}

}  // namespace

void write_png(const std::string& path, const FloatImage& image) {
  check_shape(path, image);
  if (image.channels != 1 && image.channels != 3 && image.channels != 4) throw InputError(path, "PNG needs 1, 3 or 4 channels");
  std::vector<uint8_t> bytes(image.pixels.size());
  for (size_t i = 0; i < bytes.size(); ++i) {
    const bool alpha = image.channels == 4 && i % 4 == 3;
    bytes[i] = alpha ? static_cast<uint8_t>(std::lround(std::clamp(image.pixels[i], 0.0f, 1.0f) * 255.0f)) : to_srgb8(image.pixels[i]);
  }
  // Encoded in memory, then written whole: stb's own file writing ignores a failed fwrite.
  std::string png;
  const auto append = [](void* context, void* data, int size) { static_cast<std::string*>(context)->append(static_cast<const char*>(data), size_t(size)); };
  if (stbi_write_png_to_func(append, &png, int(image.width), int(image.height), int(image.channels), bytes.data(),
                             int(image.width * image.channels)) == 0)
    throw InputError(path, "cannot encode the PNG");
  write_file(path, png);
}

void write_pfm(const std::string& path, const FloatImage& image) {
  check_shape(path, image);
  if (image.channels != 1 && image.channels != 3) throw InputError(path, "PFM holds 1 or 3 channels");
  std::string pfm = std::string(image.channels == 1 ? "Pf" : "PF") + "\n" + std::to_string(image.width) + " " +
                    std::to_string(image.height) + "\n-1.0\n";
  const size_t row = size_t(image.width) * image.channels;
  for (uint32_t y = image.height; y-- > 0;)
    pfm.append(reinterpret_cast<const char*>(image.pixels.data() + y * row), row * sizeof(float));
  write_file(path, pfm);
}

FloatImage read_pfm(const std::string& path) {
  // A FIFO would block the open, /dev/zero feed the header's words for ever: files only.
  detail::require_regular_file(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open the file");
  // Each header word read with a bound, so a file of one endless word cannot fill memory.
  std::string magic, scale_word;
  FloatImage image;
  in >> std::setw(3) >> magic;
  if (!in || (magic != "Pf" && magic != "PF")) throw InputError(path, "not a PFM file (header must start with Pf or PF)");
  if (!(in >> image.width >> image.height)) throw InputError(path, "PFM header: the width and height must be whole numbers");
  if (image.width == 0 || image.height == 0 || image.width > 65536 || image.height > 65536)
    throw InputError(path, "PFM header has an implausible size");
  in >> std::setw(32) >> scale_word;
  char* end = nullptr;
  const double scale = std::strtod(scale_word.c_str(), &end);
  if (!in || scale_word.empty() || *end != '\0' || !std::isfinite(scale) || scale == 0.0)
    throw InputError(path, "PFM header: the scale '" + scale_word + "' is not a finite non-zero number (its sign gives the byte order)");
  if (scale > 0.0) throw InputError(path, "big-endian PFM (positive scale) is not supported");
  in.get();  // the single whitespace byte after the scale
  image.channels = magic == "Pf" ? 1 : 3;
  const size_t row = size_t(image.width) * image.channels;
  image.pixels.resize(row * image.height);
  for (uint32_t y = image.height; y-- > 0;)
    if (!in.read(reinterpret_cast<char*>(image.pixels.data() + y * row), std::streamsize(row * sizeof(float))))
      throw InputError(path, "PFM data ends early (file truncated?)");
  return image;
}

bool is_supported_image_path(const std::string& path) {
  const std::string ext = detail::lower_extension(path);
  return ext == ".png" || ext == ".pfm";
}

void write_image(const std::string& path, const FloatImage& image) {
  const std::string ext = detail::lower_extension(path);
  if (ext == ".png") return write_png(path, image);
  if (ext == ".pfm") return write_pfm(path, image);
  throw InputError(path, "unknown image type '" + ext + "': use .png or .pfm");
}

}  // namespace prismoid::io
