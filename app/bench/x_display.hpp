#pragma once
// An X display for code that can only draw through X (Debian's VTK is built with X11 OpenGL
// only): when DISPLAY is unset, a private Xvfb server started for this object's lifetime, with
// DISPLAY pointing at it; when DISPLAY is already set, that display. Either way the object holds
// one client connection open while it lives: an X server resets when its last client leaves,
// and a window opened during the reset fails (VTK then aborts the process), so a display that
// VTK's windows come and go on must keep a client.
#include <memory>
#include <string>
#include <sys/types.h>

namespace prismoid::bench {

// One client connection to the display DISPLAY names (Xlib's Display*, kept opaque here).
class XConnection {
 public:
  // Retries for up to `patience_seconds` (a server resetting refuses connections briefly);
  // std::runtime_error naming DISPLAY when it cannot connect.
  explicit XConnection(double patience_seconds = 2.0);
  ~XConnection();
  XConnection(const XConnection&) = delete;
  XConnection& operator=(const XConnection&) = delete;
  void* display() const { return display_; }

 private:
  void* display_ = nullptr;
};

class XDisplay {
 public:
  // Starts Xvfb (-displayfd, -screen 0 1280x1024x24, -nolisten tcp, -noreset) when DISPLAY is
  // unset and waits until it reports its display number, up to `timeout_seconds`; then connects.
  // Throws std::runtime_error naming the problem when Xvfb is missing, exits early or stays
  // silent, or when the display cannot be opened.
  explicit XDisplay(double timeout_seconds = 30.0);
  ~XDisplay();
  XDisplay(const XDisplay&) = delete;
  XDisplay& operator=(const XDisplay&) = delete;

  // The display in use (":N"), whether started here or found in DISPLAY.
  const std::string& name() const { return name_; }
  // Whether this object started (and owns) the server.
  bool started() const { return pid_ > 0; }
  // The server's process id while it runs; 0 when none was started.
  pid_t pid() const { return pid_; }

 private:
  std::string name_;
  pid_t pid_ = 0;
  std::unique_ptr<XConnection> connection_;
};

}  // namespace prismoid::bench
