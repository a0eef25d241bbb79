#pragma once
// Small helpers shared by io's readers and writers (internal to io/).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <system_error>

#include "scene/input_error.hpp"

namespace prismoid::io::detail {

// The file's extension with its dot, lower-cased: "mesh.VTU" -> ".vtu".
inline std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// InputError naming `path` unless it is a regular file (symbolic links followed): missing, a loop
// of symbolic links, a folder, a device or pipe, or a path the system cannot look at.
inline void require_regular_file(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (status.type() == std::filesystem::file_type::not_found) throw InputError(path, "file does not exist");
  if (ec == std::errc::too_many_symbolic_link_levels) throw InputError(path, "is a loop of symbolic links, not a file");
  if (ec) throw InputError(path, "cannot be looked at: " + ec.message());
  if (status.type() == std::filesystem::file_type::directory) throw InputError(path, "is not a regular file (it is a folder)");
  if (status.type() != std::filesystem::file_type::regular) throw InputError(path, "is not a regular file");
}

}  // namespace prismoid::io::detail
