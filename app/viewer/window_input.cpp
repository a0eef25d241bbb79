#include "app/viewer/window_input.hpp"

#include "app/viewer/mouse_bindings.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

void handle_mouse(Window& window, CameraController& camera, MouseState& mouse, VkExtent2D viewport_extent, bool ui_wants_mouse,
                  bool ui_wants_keyboard, double seconds) {
  GLFWwindow* w = window.get();
  glm::dvec2 now;
  glfwGetCursorPos(w, &now.x, &now.y);
  const glm::dvec2 delta = now - mouse.last;
  mouse.last = now;
  MouseButtons buttons;
  buttons.left = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  buttons.middle = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  buttons.right = glfwGetMouseButton(w, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  buttons.shift = glfwGetKey(w, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(w, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  const glm::dvec2 viewport(viewport_extent.width, viewport_extent.height);
  const auto gesture = drag_gesture(buttons, camera.flying());
  if (!gesture) mouse.dragging = false;
  else if (!mouse.dragging && !ui_wants_mouse) mouse.dragging = true;  // drags that start on a panel stay the panel's
  if (mouse.dragging && gesture && (delta.x != 0.0 || delta.y != 0.0)) apply_drag(camera, *gesture, delta, viewport);
  const double scroll = window.take_scroll();
  if (!ui_wants_mouse && scroll != 0.0) camera.zoom(scroll);
  if (camera.flying() && !ui_wants_keyboard) {
    auto held = [&](int key) { return glfwGetKey(w, key) == GLFW_PRESS ? 1.0 : 0.0; };
    const glm::dvec3 direction(held(GLFW_KEY_D) - held(GLFW_KEY_A), held(GLFW_KEY_E) - held(GLFW_KEY_Q), held(GLFW_KEY_W) - held(GLFW_KEY_S));
    if (direction != glm::dvec3(0.0)) camera.fly_move(direction, seconds);
  }
}

namespace {

vk::Instance presenting_instance(bool validation) {
  if (!glfwVulkanSupported()) throw vk::NoSuitableDevice("GLFW found no Vulkan loader able to present");
  uint32_t ext_count = 0;
  const char** exts = glfwGetRequiredInstanceExtensions(&ext_count);
  vk::InstanceOptions options;
  options.validation = validation;
  for (uint32_t i = 0; i < ext_count; ++i) options.extensions.emplace_back(exts[i]);
  return vk::Instance(options);
}

}  // namespace

PresentingDevice::PresentingDevice(bool validation, std::optional<uint32_t> device_index)
    : instance(presenting_instance(validation)),
      devices(vk::query_devices(instance.get())),
      caps(vk::select_device(devices, device_index)),
      device(instance, caps, {.presentation = true}) {}

void recreate_swapchain(vk::Swapchain& swapchain, const Window& window, ImGuiLayer& ui, ViewerReport& report) {
  swapchain.recreate(window.framebuffer_extent());
  ui.swapchain_changed();
  ++report.swapchain_recreations;
}

void finish_capture(SwapchainCapture& capture, ViewerReport& report, const std::vector<std::string>& inputs,
                    const std::function<void(const std::string&)>& message) {
  try {
    if (const auto written = capture.finish(inputs)) report.files_written.push_back(*written);
  } catch (const std::exception& e) {  // an unwritable path: say so, keep the window
    message(e.what());
  }
}

}  // namespace prismoid::app
