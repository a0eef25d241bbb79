#include "app/viewer/recent_files.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <system_error>

namespace prismoid::app {

namespace {

bool is_spec(const std::string& path) {
  return path.empty() || path.rfind("field:", 0) == 0 || path.rfind("grid:", 0) == 0 ||
         (path.rfind("ball", 0) == 0 && (path.size() == 4 || path[4] == ':'));
}

}  // namespace

std::filesystem::path recent_files_path() {
  if (const char* config = std::getenv("XDG_CONFIG_HOME"); config && *config)
    return std::filesystem::path(config) / "prismoid" / "recent.txt";
  if (const char* home = std::getenv("HOME"); home && *home) return std::filesystem::path(home) / ".config" / "prismoid" / "recent.txt";
  return {};
}

std::vector<std::string> read_recent(const std::filesystem::path& file) {
  std::vector<std::string> list;
  std::ifstream in(file);
  for (std::string line; list.size() < kMaxRecent && std::getline(in, line);)
    if (!line.empty() && std::find(list.begin(), list.end(), line) == list.end()) list.push_back(line);
  return list;
}

bool write_recent(const std::filesystem::path& file, const std::vector<std::string>& list) {
  if (file.empty()) return false;
  std::error_code error;
  std::filesystem::create_directories(file.parent_path(), error);
  std::ofstream out(file, std::ios::trunc);
  for (const std::string& path : list) out << path << "\n";
  return bool(out);
}

std::vector<std::string> with_opened(std::vector<std::string> list, const std::string& path) {
  if (is_spec(path)) return list;
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(path, error);
  const std::string entry = error ? path : absolute.lexically_normal().string();
  list.erase(std::remove(list.begin(), list.end(), entry), list.end());
  list.insert(list.begin(), entry);
  if (list.size() > kMaxRecent) list.resize(kMaxRecent);
  return list;
}

std::vector<std::string> remember_opened(const std::filesystem::path& file, const std::string& path) {
  std::vector<std::string> list = with_opened(read_recent(file), path);
  write_recent(file, list);
  return list;
}

}  // namespace prismoid::app
