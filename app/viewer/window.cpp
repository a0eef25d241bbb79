#include "app/viewer/window.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include "renderer/vk/error.hpp"

namespace prismoid::app {

GlfwSession::GlfwSession() {
  glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "[prismoid] GLFW error %d: %s\n", code, text); });
  if (!glfwInit()) throw std::runtime_error("cannot open a window: GLFW could not connect to a display (is DISPLAY set?)");
}

GlfwSession::~GlfwSession() { glfwTerminate(); }

Window::Window(uint32_t width, uint32_t height, const char* title) {
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  handle_ = glfwCreateWindow(int(width), int(height), title, nullptr, nullptr);
  if (!handle_) throw std::runtime_error("cannot create the window");
  glfwSetWindowUserPointer(handle_, this);
  // Installed before Dear ImGui's, which then calls these after its own.
  glfwSetKeyCallback(handle_, [](GLFWwindow* w, int key, int, int action, int mods) {
    if (action == GLFW_PRESS) static_cast<Window*>(glfwGetWindowUserPointer(w))->keys_.push_back({key, mods});
  });
  glfwSetScrollCallback(handle_, [](GLFWwindow* w, double, double dy) { static_cast<Window*>(glfwGetWindowUserPointer(w))->scroll_ += dy; });
  glfwSetDropCallback(handle_, [](GLFWwindow* w, int count, const char** paths) {
    static_cast<Window*>(glfwGetWindowUserPointer(w))->queue_drop(std::vector<std::string>(paths, paths + count));
  });
}

Window::~Window() { glfwDestroyWindow(handle_); }

VkExtent2D Window::framebuffer_extent() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(handle_, &w, &h);
  return {uint32_t(std::max(w, 0)), uint32_t(std::max(h, 0))};
}

std::vector<KeyPress> Window::take_keys() { return std::exchange(keys_, {}); }

double Window::take_scroll() { return std::exchange(scroll_, 0.0); }

std::vector<std::vector<std::string>> Window::take_drops() { return std::exchange(drops_, {}); }

void Window::queue_drop(std::vector<std::string> paths) {
  if (!paths.empty()) drops_.push_back(std::move(paths));
}

Surface::Surface(VkInstance instance, GLFWwindow* window) : instance_(instance) {
  vk::check(glfwCreateWindowSurface(instance, window, nullptr, &handle_), "glfwCreateWindowSurface");
}

Surface::~Surface() { vkDestroySurfaceKHR(instance_, handle_, nullptr); }

}  // namespace prismoid::app
