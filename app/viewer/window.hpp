#pragma once
// The window's platform side: GLFW, one window, its Vulkan surface, and the input events the
// frame loop consumes (key presses, wheel steps and dropped files queued by callbacks, so none is missed
// between two frames).
#include <cstdint>
#include <string>
#include <vector>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

namespace prismoid::app {

class GlfwSession {
 public:
  GlfwSession();
  ~GlfwSession();
  GlfwSession(const GlfwSession&) = delete;
  GlfwSession& operator=(const GlfwSession&) = delete;
};

struct KeyPress {
  int key = 0;   // GLFW_KEY_*
  int mods = 0;  // GLFW_MOD_*
};

class Window {
 public:
  Window(uint32_t width, uint32_t height, const char* title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  GLFWwindow* get() const { return handle_; }
  VkExtent2D framebuffer_extent() const;
  // Events since the last call.
  std::vector<KeyPress> take_keys();
  double take_scroll();
  // Files dropped onto the window, one list per drop. Scripts queue drops here too, so they
  // take the same path as a drop from the desktop.
  std::vector<std::vector<std::string>> take_drops();
  void queue_drop(std::vector<std::string> paths);

 private:
  GLFWwindow* handle_ = nullptr;
  std::vector<KeyPress> keys_;
  double scroll_ = 0.0;
  std::vector<std::vector<std::string>> drops_;
};

class Surface {
 public:
  Surface(VkInstance instance, GLFWwindow* window);
  ~Surface();
  Surface(const Surface&) = delete;
  Surface& operator=(const Surface&) = delete;
  VkSurfaceKHR get() const { return handle_; }

 private:
  VkInstance instance_;
  VkSurfaceKHR handle_ = VK_NULL_HANDLE;
};

}  // namespace prismoid::app
