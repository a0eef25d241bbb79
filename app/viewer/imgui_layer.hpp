#pragma once
// Dear ImGui on the window: its context, the GLFW and Vulkan backends, and the render pass that
// draws the UI into the swapchain image after the frame's display image has been blitted there.
// One instance per window; it owns every Vulkan object it creates.
#include <vector>

#include "app/viewer/window.hpp"
#include "renderer/vk/handle.hpp"

namespace prismoid::vk {
class Device;
class Swapchain;
}  // namespace prismoid::vk

namespace prismoid::app {

class ImGuiLayer {
 public:
  ImGuiLayer(const vk::Device& device, GLFWwindow* window, const vk::Swapchain& swapchain);
  ~ImGuiLayer();  // the device must be idle
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;

  // Starts a UI frame: ImGui:: calls are valid until finish_frame().
  void begin_frame();
  void finish_frame();  // ImGui::Render()

  // Rebuilds the per-image views and framebuffers (call after the swapchain was recreated).
  void swapchain_changed();

  // Records the UI over swapchain image `index`, which is in TRANSFER_DST_OPTIMAL layout (the
  // blit); it ends in PRESENT_SRC_KHR. With draw false only the layout changes.
  void record(VkCommandBuffer cmd, uint32_t index, bool draw);

  // Whether the UI wants the mouse or keyboard (the pointer is over a panel, a text box has focus).
  bool wants_mouse() const;
  bool wants_keyboard() const;

 private:
  const vk::Device& device_;
  const vk::Swapchain& swapchain_;
  vk::UniqueDescriptorPool pool_;
  vk::UniqueRenderPass render_pass_;
  std::vector<vk::UniqueImageView> views_;
  std::vector<vk::UniqueFramebuffer> framebuffers_;
};

}  // namespace prismoid::app
