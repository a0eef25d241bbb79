#pragma once
// The recent-files list: the datasets opened last, most recent first, at most kMaxRecent,
// kept in $XDG_CONFIG_HOME/prismoid/recent.txt (else ~/.config/prismoid/recent.txt), one path
// a line. Files are stored as absolute paths; specs (field:, grid:, ball) are not files and
// are not kept.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace prismoid::app {

inline constexpr size_t kMaxRecent = 10;

// Where the list lives; empty when neither XDG_CONFIG_HOME nor HOME is set.
std::filesystem::path recent_files_path();

// The list in `file` (missing file: empty list; blank lines skipped; at most kMaxRecent).
std::vector<std::string> read_recent(const std::filesystem::path& file);
// Writes the list, creating the directory; false when it cannot (the list is a convenience:
// failing to keep it is not an error).
bool write_recent(const std::filesystem::path& file, const std::vector<std::string>& list);

// The list after opening `path`: moved (or added) to the front, duplicates removed, cut to
// kMaxRecent. `path` is made absolute; a spec leaves the list as it is.
std::vector<std::string> with_opened(std::vector<std::string> list, const std::string& path);
// Reads, updates with `path` and writes back the list at `file`; returns the new list.
std::vector<std::string> remember_opened(const std::filesystem::path& file, const std::string& path);

}  // namespace prismoid::app
