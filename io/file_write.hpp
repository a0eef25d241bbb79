#pragma once
// Writing a whole file so that a failure is never silent: every write's result is checked, the
// file is synced to the disk before it counts as written, and the error names the cause (a full
// disk says "No space left on device"). Writers that build their bytes in memory (PNG, PFM,
// .vtu, .vdb) end here; where the file goes (a temporary beside the output, renamed into place)
// is the caller's: app/common/output_files.hpp.
#include <string>
#include <string_view>

namespace prismoid::io {

// Creates or truncates `path` and writes `bytes` into it, then fsync. InputError(path,
// "cannot be written: <the system's reason>") on any failure (the caller removes what is left).
void write_file(const std::string& path, std::string_view bytes);

// fsync of a file another library wrote: InputError(path, "cannot be written: ...") when the
// disk refuses what it held in its cache.
void sync_file(const std::string& path);

}  // namespace prismoid::io
