#pragma once
// What every fuzz target shares: bad input must end in an InputError (the CLI's exit code 2);
// any other exception escaping a parser, a crash, a leak or undefined behaviour is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <unistd.h>

#include "scene/input_error.hpp"

namespace prismoid::fuzz {

// Runs `body`, swallowing only InputError.
template <typename Body>
void expect_input_errors_only(Body&& body) {
  try {
    body();
  } catch (const InputError&) {
  }
}

// A property a parser's output must have; failing it aborts so that libFuzzer keeps the input.
inline void require(bool holds, const char* what) {
  if (holds) return;
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}

// The path-based readers (zlib's gzopen) read a file: each input is written to one scratch file
// per process, in $TMPDIR, else in /dev/shm (memory: three times the runs of a disk's /tmp),
// removed at exit.
class ScratchFile {
 public:
  explicit ScratchFile(const char* suffix) {
    const char* tmpdir = std::getenv("TMPDIR");
    const std::string dir = tmpdir && *tmpdir ? tmpdir : ::access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    path_ = dir + "/prismoid-fuzz-" + std::to_string(::getpid()) + suffix;
  }
  ~ScratchFile() { std::remove(path_.c_str()); }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::string& write(const uint8_t* data, size_t size) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    require(f != nullptr, "scratch file can be written");
    require(size == 0 || std::fwrite(data, 1, size, f) == size, "scratch file takes the whole input");
    std::fclose(f);
    return path_;
  }

 private:
  std::string path_;
};

}  // namespace prismoid::fuzz
