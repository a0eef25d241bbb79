#pragma once
// What every window loop does with GLFW's input and the queue, shared by the volume window
// (viewer.cpp) and the surface window (surface_viewer.cpp): mouse drags, the wheel and fly
// mode's held keys applied to the camera (ParaView's bindings, mouse_bindings.hpp), and the
// frame's submission.
#include <vulkan/vulkan.h>

#include <glm/vec2.hpp>

#include <optional>
#include <vector>

#include <functional>
#include <string>

#include "app/viewer/camera_controller.hpp"
#include "app/viewer/imgui_layer.hpp"
#include "app/viewer/screenshot.hpp"
#include "app/viewer/viewer.hpp"
#include "app/viewer/window.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/swapchain.hpp"

namespace prismoid::app {

struct MouseState {
  glm::dvec2 last{0.0};
  bool dragging = false;  // a drag that began outside the panels
};

// Reads the cursor, buttons, wheel and held keys; `ui_wants_mouse` keeps drags that start on a
// panel the panel's. `seconds` since the last frame (fly mode's movement).
void handle_mouse(Window& window, CameraController& camera, MouseState& mouse, VkExtent2D viewport, bool ui_wants_mouse,
                  bool ui_wants_keyboard, double seconds);

// GLFW, an instance with the extensions GLFW needs to present, and a device that presents
// (NoSuitableDevice when GLFW finds no Vulkan loader or no device can present).
struct PresentingDevice {
  PresentingDevice(bool validation, std::optional<uint32_t> device_index);
  GlfwSession glfw;
  vk::Instance instance;
  std::vector<vk::DeviceCapabilities> devices;
  const vk::DeviceCapabilities& caps;
  vk::Device device;
};

// A new swapchain at the window's framebuffer size (resized or out of date), the UI told, the
// report counting it.
void recreate_swapchain(vk::Swapchain& swapchain, const Window& window, ImGuiLayer& ui, ViewerReport& report);
// After the frame a screenshot was recorded in has finished: writes it (never over one of
// `inputs`) and lists it in the report; a failure goes to `message` (the window stays).
void finish_capture(SwapchainCapture& capture, ViewerReport& report, const std::vector<std::string>& inputs,
                    const std::function<void(const std::string&)>& message);

}  // namespace prismoid::app
