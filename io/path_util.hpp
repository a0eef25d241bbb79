#pragma once
// Small helpers shared by io's readers and writers (internal to io/).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace prismoid::io::detail {

// The file's extension with its dot, lower-cased: "mesh.VTU" -> ".vtu".
inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace prismoid::io::detail
