#include "io/transfer_function_io.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "io/path_util.hpp"
#include "scene/input_error.hpp"

namespace prismoid::io {

namespace {

// ParaView stores display (sRGB) colours; rendering works in linear RGB.
double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double linear_to_srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

std::vector<double> numbers(const nlohmann::json& entry, const char* key, size_t stride, const std::string& path) {
  const auto& list = entry.at(key);
  if (!list.is_array() || list.empty() || list.size() % stride != 0)
    throw InputError(path, std::string("\"") + key + "\" must hold groups of " + std::to_string(stride) + " numbers");
  if (list.size() / stride > kMaxTransferFunctionPoints)
    throw InputError(path, std::string("\"") + key + "\" holds " + std::to_string(list.size() / stride) + " points; at most " +
                               std::to_string(kMaxTransferFunctionPoints) + " are read (colour maps hold a few hundred)");
  std::vector<double> v;
  for (const auto& x : list) {
    if (!x.is_number()) throw InputError(path, std::string("\"") + key + "\" holds something that is not a number");
    v.push_back(x.get<double>());
  }
  return v;
}

}  // namespace

volume::TransferFunction read_paraview_colormap(const std::string& path) {
  detail::require_regular_file(path);
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot be read");
  return parse_paraview_colormap(in, path);
}

volume::TransferFunction parse_paraview_colormap(std::istream& in, const std::string& path) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, std::string("is not valid JSON (") + e.what() + ")");
  }
  const nlohmann::json& entry = doc.is_array() ? (doc.empty() ? doc : doc.front()) : doc;
  if (!entry.is_object() || !entry.contains("RGBPoints"))
    throw InputError(path, "is not a ParaView colour map: no \"RGBPoints\"");
  volume::TransferFunction tf;
  tf.name = entry.contains("Name") && entry["Name"].is_string() ? entry["Name"].get<std::string>() : path;
  const std::vector<double> rgb = numbers(entry, "RGBPoints", 4, path);
  const double lo = rgb.front(), hi = rgb[rgb.size() - 4];
  const double span = hi > lo ? hi - lo : 1.0;
  for (size_t i = 0; i < rgb.size(); i += 4) {
    for (int c = 1; c <= 3; ++c)
      if (!(rgb[i + c] >= 0.0 && rgb[i + c] <= 1.0)) throw InputError(path, "colour components must lie in [0, 1]");
    tf.color.push_back({(rgb[i] - lo) / span, {srgb_to_linear(rgb[i + 1]), srgb_to_linear(rgb[i + 2]), srgb_to_linear(rgb[i + 3])}});
  }
  if (entry.contains("Points")) {
    const std::vector<double> op = numbers(entry, "Points", 4, path);
    for (size_t i = 0; i < op.size(); i += 4) {
      if (std::abs(op[i + 2] - 0.5) > 1e-9 || std::abs(op[i + 3]) > 1e-9)
        throw InputError(path, "opacity point " + std::to_string(i / 4) +
                                   " has a midpoint or sharpness other than 0.5 / 0 (only linear segments are supported)");
      tf.opacity.push_back({(op[i] - lo) / span, op[i + 1]});
    }
  } else {
    tf.opacity = {{0.0, 0.0}, {1.0, 1.0}};
  }
  const std::string name = tf.name;
  tf.name = path;  // errors name the file
  volume::validate(tf);
  tf.name = name;
  return tf;
}

void write_paraview_colormap(const std::string& path, const volume::TransferFunction& tf) {
  nlohmann::json entry;
  entry["Name"] = tf.name;
  entry["ColorSpace"] = "RGB";
  nlohmann::json rgb = nlohmann::json::array(), points = nlohmann::json::array();
  for (const auto& p : tf.color)
    for (double v : {p.x, linear_to_srgb(p.rgb.r), linear_to_srgb(p.rgb.g), linear_to_srgb(p.rgb.b)}) rgb.push_back(v);
  for (const auto& p : tf.opacity)
    for (double v : {p.x, p.opacity, 0.5, 0.0}) points.push_back(v);
  entry["RGBPoints"] = rgb;
  entry["Points"] = points;
  std::ofstream out(path);
  if (!out || !(out << nlohmann::json::array({entry}).dump(2) << "\n") || !out.flush()) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    throw InputError(path, "cannot be written");
  }
}

volume::TransferFunction transfer_function_from(const std::string& preset_or_path) {
  for (const auto& name : volume::preset_names())
    if (name == preset_or_path) return volume::preset(name);
  // Anything at that path (a folder, a loop of symbolic links) is read as a file, and refused as one.
  std::error_code ec;
  if (std::filesystem::symlink_status(preset_or_path, ec).type() != std::filesystem::file_type::not_found && !ec)
    return read_paraview_colormap(preset_or_path);
  return volume::preset(preset_or_path);  // throws, listing the presets
}

}  // namespace prismoid::io
