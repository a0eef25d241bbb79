#include "app/common/terminal_progress.hpp"

#include <cstdio>
#include <unistd.h>

namespace prismoid::app {

namespace {

volatile std::sig_atomic_t g_cancel_requested = 0;
void request_cancel(int) { g_cancel_requested = 1; }

}  // namespace

TerminalProgress::TerminalProgress(std::string label)
    : label_(std::move(label)), start_(std::chrono::steady_clock::now()), last_draw_(start_), terminal_(::isatty(STDERR_FILENO) == 1) {
  g_cancel_requested = 0;
  previous_handler_ = std::signal(SIGINT, request_cancel);
  if (previous_handler_ == SIG_IGN) std::signal(SIGINT, SIG_IGN);  // a background job: Ctrl-C is not ours
}

TerminalProgress::~TerminalProgress() {
  std::signal(SIGINT, previous_handler_ == SIG_ERR ? SIG_DFL : previous_handler_);
  if (drawn_) {
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    std::fprintf(stderr, "\r\033[K%s: %.1f s\n", label_.c_str(), seconds);
  }
}

void TerminalProgress::throw_if_cancelled(const std::string& source) const {
  if (g_cancel_requested) throw io::Cancelled(source);
}

io::Progress TerminalProgress::callback() {
  return [this](double fraction, const std::string& stage) { return update(fraction, stage); };
}

bool TerminalProgress::update(double fraction, const std::string& stage) {
  if (g_cancel_requested) return false;
  const auto now = std::chrono::steady_clock::now();
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (!terminal_ || seconds < 1.0 || now - last_draw_ < std::chrono::milliseconds(100)) return true;
  last_draw_ = now;
  drawn_ = true;
  if (fraction >= 0.0) {
    const int filled = static_cast<int>(fraction * 30.0 + 0.5);
    std::fprintf(stderr, "\r\033[K%s: [%-30.*s] %3d%% %s, %.1f s (Ctrl-C cancels)", label_.c_str(), filled,
                 "==============================", static_cast<int>(fraction * 100.0 + 0.5), stage.c_str(), seconds);
  } else {
    std::fprintf(stderr, "\r\033[K%s: %s, %.1f s (Ctrl-C cancels)", label_.c_str(), stage.c_str(), seconds);
  }
  std::fflush(stderr);
  return true;
}

}  // namespace prismoid::app
