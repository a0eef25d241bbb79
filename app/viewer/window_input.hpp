#pragma once
// What every window loop does with GLFW's input and the queue, shared by the volume window
// (viewer.cpp) and the surface window (surface_viewer.cpp): mouse drags, the wheel and fly
// mode's held keys applied to the camera (ParaView's bindings, mouse_bindings.hpp), and the
// frame's submission.
#include <vulkan/vulkan.h>

#include <glm/vec2.hpp>

#include "app/viewer/camera_controller.hpp"
#include "app/viewer/window.hpp"
#include "renderer/vk/device.hpp"

namespace prismoid::app {

struct MouseState {
  glm::dvec2 last{0.0};
  bool dragging = false;  // a drag that began outside the panels
};

// Reads the cursor, buttons, wheel and held keys; `ui_wants_mouse` keeps drags that start on a
// panel the panel's. `seconds` since the last frame (fly mode's movement).
void handle_mouse(Window& window, CameraController& camera, MouseState& mouse, VkExtent2D viewport, bool ui_wants_mouse,
                  bool ui_wants_keyboard, double seconds);

// Waits for the acquired image before the blit writes it; signals `done` for presentation.
void submit_frame(const vk::Device& device, VkCommandBuffer cmd, VkSemaphore acquired, VkSemaphore done, VkFence fence);

}  // namespace prismoid::app
