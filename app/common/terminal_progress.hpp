#pragma once
// A progress bar on the terminal for long loads (converting images, TetGen): drawn on stderr
// when stderr is a terminal and the work has run for over a second; Ctrl-C while it is alive
// cancels the work (its callback returns false, the work throws io::Cancelled).
#include <chrono>
#include <csignal>
#include <string>

#include "io/progress.hpp"

namespace prismoid::app {

class TerminalProgress {
 public:
  explicit TerminalProgress(std::string label);
  ~TerminalProgress();
  TerminalProgress(const TerminalProgress&) = delete;
  TerminalProgress& operator=(const TerminalProgress&) = delete;

  io::Progress callback();
  // Throws io::Cancelled(source) when Ctrl-C came after the work's last progress report.
  void throw_if_cancelled(const std::string& source) const;

 private:
  bool update(double fraction, const std::string& stage);

  std::string label_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
  bool terminal_ = false;
  void (*previous_handler_)(int) = SIG_DFL;
};

}  // namespace prismoid::app
