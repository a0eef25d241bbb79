#include "renderer/frame/frame_renderer.hpp"

#include "renderer/vk/device.hpp"

namespace prismoid::frame {

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& mesh)
    : device_(device), mesh_(volume::upload(device, mesh)), bounds_(bounds_of(mesh)), interval_(device),
      offscreen_timer_(device, 16) {}

void FrameRenderer::resize(VkExtent2D extent) {
  if (extent.width == targets_.extent.width && extent.height == targets_.extent.height) return;
  device_.wait_idle();
  targets_ = volume::create_targets(device_, extent);
}

void FrameRenderer::record(VkCommandBuffer cmd, const Camera& camera, const FrameSettings& settings, vk::GpuTimer& timer) {
  interval_.record(cmd, mesh_, targets_, camera, settings.resolve, timer);
}

OffscreenFrame FrameRenderer::render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent) {
  resize(extent);
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    offscreen_timer_.reset(cmd);
    record(cmd, camera, settings, offscreen_timer_);
  });
  OffscreenFrame frame;
  frame.width = extent.width;
  frame.height = extent.height;
  const size_t pixels = size_t(extent.width) * extent.height;
  frame.quantity.resize(pixels);
  frame.display.resize(pixels * 4);
  vk::read_image(device_, targets_.quantity, sizeof(float), std::as_writable_bytes(std::span(frame.quantity)));
  vk::read_image(device_, targets_.display, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.display)));
  frame.passes = offscreen_timer_.read();
  return frame;
}

}  // namespace prismoid::frame
