#include "app/bench/x_display.hpp"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <poll.h>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include <X11/Xlib.h>

namespace prismoid::bench {

namespace {

// Stops and reaps the server: SIGTERM, then SIGKILL if it has not exited after a second.
void stop(pid_t pid) {
  ::kill(pid, SIGTERM);
  for (int i = 0; i < 100; ++i) {
    int status = 0;
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid || (r < 0 && errno != EINTR)) return;
    ::usleep(10000);
  }
  ::kill(pid, SIGKILL);
  while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
  }
}

std::string exit_description(int status) {
  if (WIFEXITED(status)) {
    if (WEXITSTATUS(status) == 127) return "could not be run (is the xvfb package installed? Xvfb is not on PATH)";
    return "exited with status " + std::to_string(WEXITSTATUS(status)) + " before reporting a display";
  }
  if (WIFSIGNALED(status)) return "was killed by signal " + std::to_string(WTERMSIG(status)) + " before reporting a display";
  return "stopped before reporting a display";
}

}  // namespace

XDisplay::XDisplay(double timeout_seconds) {
  if (const char* d = std::getenv("DISPLAY"); d && *d) {
    name_ = d;
    connection_ = std::make_unique<XConnection>();
    return;
  }
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("Xvfb: cannot make a pipe: ") + std::strerror(errno));
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw std::runtime_error(std::string("Xvfb: cannot fork: ") + std::strerror(errno));
  }
  if (pid == 0) {
    // The child: only async-signal-safe calls until exec. The server dies with its parent.
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    const int write_fd = ::fcntl(fds[1], F_DUPFD, 3);  // a copy without close-on-exec
    const int null_fd = ::open("/dev/null", O_RDWR);
    if (null_fd >= 0) {
      ::dup2(null_fd, STDIN_FILENO);
      ::dup2(null_fd, STDOUT_FILENO);
      ::dup2(null_fd, STDERR_FILENO);
    }
    char fd_text[16];
    int n = 0;
    char digits[16];
    for (int v = write_fd; n == 0 || v > 0; v /= 10) digits[n++] = static_cast<char>('0' + v % 10);
    for (int i = 0; i < n; ++i) fd_text[i] = digits[n - 1 - i];
    fd_text[n] = '\0';
    char* const argv[] = {const_cast<char*>("Xvfb"), const_cast<char*>("-displayfd"), fd_text,
                          const_cast<char*>("-screen"), const_cast<char*>("0"), const_cast<char*>("1280x1024x24"),
                          const_cast<char*>("-nolisten"), const_cast<char*>("tcp"), const_cast<char*>("-noreset"), nullptr};
    ::execvp("Xvfb", argv);
    ::_exit(127);
  }
  ::close(fds[1]);
  // Xvfb writes the display number and a newline to the fd once it accepts connections.
  std::string text;
  std::string problem;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  while (text.find('\n') == std::string::npos) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) {
      problem = "did not report a display within " + std::to_string(timeout_seconds) + " s";
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    const int r = ::poll(&p, 1, static_cast<int>(left));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) continue;
    char buffer[64];
    const ssize_t got = ::read(fds[0], buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {  // the pipe closed: the server exited (or exec failed)
      int status = 0;
      while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      ::close(fds[0]);
      throw std::runtime_error("Xvfb " + exit_description(status));
    }
    text.append(buffer, static_cast<size_t>(got));
  }
  ::close(fds[0]);
  if (problem.empty()) {
    const std::string number = text.substr(0, text.find('\n'));
    if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos)
      problem = "reported '" + number + "' instead of a display number";
    else
      name_ = ":" + number;
  }
  if (!problem.empty()) {
    stop(pid);
    throw std::runtime_error("Xvfb " + problem);
  }
  pid_ = pid;
  ::setenv("DISPLAY", name_.c_str(), 1);
  try {
    connection_ = std::make_unique<XConnection>();
  } catch (...) {
    ::unsetenv("DISPLAY");
    stop(pid_);
    throw;
  }
}

XDisplay::~XDisplay() {
  connection_.reset();
  if (pid_ <= 0) return;
  ::unsetenv("DISPLAY");
  stop(pid_);
}

XConnection::XConnection(double patience_seconds) {
  const char* name = std::getenv("DISPLAY");
  if (!name || !*name) throw std::runtime_error("no X display: DISPLAY is not set (the VTK peers draw through X; see bench::XDisplay)");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(patience_seconds);
  while (!(display_ = ::XOpenDisplay(nullptr))) {
    if (std::chrono::steady_clock::now() >= deadline)
      throw std::runtime_error(std::string("cannot open the X display ") + name + " (is its server running, and XAUTHORITY right?)");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

XConnection::~XConnection() {
  if (display_) ::XCloseDisplay(static_cast<Display*>(display_));
}

}  // namespace prismoid::bench
