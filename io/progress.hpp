#pragma once
// Progress of long io work (loading, converting, tetrahedralizing), for a terminal bar or the
// viewer: `fraction` in [0, 1], or negative while the work cannot tell how far it is (TetGen).
// The callback returns false to cancel; the work then stops and throws Cancelled.
#include <functional>
#include <stdexcept>
#include <string>

namespace prismoid::io {

using Progress = std::function<bool(double fraction, const std::string& stage)>;

class Cancelled : public std::runtime_error {
 public:
  explicit Cancelled(const std::string& source) : std::runtime_error(source + ": cancelled") {}
};

// Calls `progress` (if any) and throws Cancelled(source) when it asks to stop.
inline void report(const Progress& progress, double fraction, const std::string& stage, const std::string& source) {
  if (progress && !progress(fraction, stage)) throw Cancelled(source);
}

// `progress` for a step that fills [start, end] of the whole: fraction f becomes
// start + f (end - start); an unknown fraction (negative) stays unknown.
inline Progress scaled(const Progress& progress, double start, double end) {
  if (!progress) return {};
  return [progress, start, end](double fraction, const std::string& stage) {
    return progress(fraction < 0.0 ? fraction : start + fraction * (end - start), stage);
  };
}

}  // namespace prismoid::io
