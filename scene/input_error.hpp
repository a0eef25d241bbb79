#pragma once
// Bad user input: names the file (or option) and what is wrong with it. The CLI maps it to
// exit code 2 and prints one line.
#include <stdexcept>
#include <string>

namespace prismoid {

class InputError : public std::runtime_error {
 public:
  InputError(std::string source, const std::string& problem)
      : std::runtime_error(source + ": " + problem), source_(std::move(source)) {}
  const std::string& source() const { return source_; }

 private:
  std::string source_;
};

}  // namespace prismoid
