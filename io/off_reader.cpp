#include "io/off_reader.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "scene/input_error.hpp"

namespace prismoid::io::detail {

namespace {

// Counts past this are refused before anything is allocated for them: OFF files of real
// meshes hold a few million elements, and the count alone must not exhaust memory.
constexpr double kMaxCount = 1e9;

class Tokens {
 public:
  Tokens(std::istream& in, const std::string& name) : name_(name) {
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream words(line.substr(0, line.find('#')));
      std::string w;
      while (words >> w) tokens_.push_back(std::move(w));
    }
  }
  size_t left() const { return tokens_.size() - next_; }
  const std::string& take(const char* what) {
    if (next_ >= tokens_.size()) throw InputError(name_, std::string("ends early: expected ") + what);
    return tokens_[next_++];
  }
  double number(const char* what) {
    const std::string& t = take(what);
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(v)) throw InputError(name_, std::string("bad ") + what + " '" + t + "'");
    return v;
  }
  uint32_t count(const char* what) {
    const double v = number(what);
    if (v < 0 || v != std::floor(v) || v > kMaxCount) throw InputError(name_, std::string("bad ") + what);
    return static_cast<uint32_t>(v);
  }

 private:
  const std::string& name_;
  std::vector<std::string> tokens_;
  size_t next_ = 0;
};

}  // namespace

OffPolygons parse_off(std::istream& in, const std::string& name) {
  Tokens tokens(in, name);
  if (tokens.take("the OFF header") != "OFF") throw InputError(name, "is not an OFF file (no 'OFF' header)");
  const uint32_t nv = tokens.count("vertex count"), nf = tokens.count("face count");
  tokens.count("edge count");
  OffPolygons off;
  // Each vertex takes three tokens and each face at least one: a count beyond what the file holds
  // is an early end, found before reserving memory for it.
  if (3 * uint64_t(nv) + nf > tokens.left())
    throw InputError(name, "ends early: the header promises " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
                               " faces, more than the file holds");
  off.points.reserve(nv);
  for (uint32_t i = 0; i < nv; ++i) {
    const double x = tokens.number("coordinate"), y = tokens.number("coordinate"), z = tokens.number("coordinate");
    off.points.emplace_back(x, y, z);
  }
  off.faces.reserve(nf);
  for (uint32_t f = 0; f < nf; ++f) {
    const uint32_t n = tokens.count("face size");
    if (n > tokens.left()) throw InputError(name, "ends early: face " + std::to_string(f) + " has " + std::to_string(n) + " vertices");
    std::vector<uint32_t> face;
    face.reserve(n);
    for (uint32_t k = 0; k < n; ++k) {
      const uint32_t v = tokens.count("vertex index");
      if (v >= nv) throw InputError(name, "face " + std::to_string(f) + " names vertex " + std::to_string(v) + " of " + std::to_string(nv));
      face.push_back(v);
    }
    off.faces.push_back(std::move(face));
  }
  return off;
}

}  // namespace prismoid::io::detail
