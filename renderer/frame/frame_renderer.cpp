#include "renderer/frame/frame_renderer.hpp"

#include <chrono>

#include "renderer/vk/device.hpp"

namespace prismoid::frame {

const char* ordering_name(Ordering ordering) {
  switch (ordering) {
    case Ordering::MeshOrder: return "mesh-order";
    case Ordering::GpuSort: return "gpu-sort";
    case Ordering::Exact: return "exact";
  }
  return "?";
}

// The visibility orderings a frame may use, made on first use.
struct FrameRenderer::Orderings {
  const vk::Buffer* order = nullptr;  // what the next record() draws with (nullptr: mesh order)
};

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& mesh)
    : device_(device), mesh_(volume::upload(device, mesh)), bounds_(bounds_of(mesh)), interval_(device),
      orderings_(std::make_unique<Orderings>()), offscreen_timer_(device, 16) {}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::resize(VkExtent2D extent) {
  if (extent.width == targets_.extent.width && extent.height == targets_.extent.height) return;
  device_.wait_idle();
  targets_ = volume::create_targets(device_, extent);
}

FrameReport FrameRenderer::prepare(const Camera& camera, const FrameSettings& settings) {
  (void)camera;
  FrameReport report;
  const double table_ms = interval_.prepare(mesh_, settings.resolve);
  if (table_ms > 0.0) report.cpu_passes.push_back({"preintegrate", table_ms});
  orderings_->order = nullptr;
  if (!volume::order_dependent(settings.resolve.quantity)) {
    report.ordering = "none (order-independent)";
    report.order_exact = true;
    return report;
  }
  report.ordering = ordering_name(settings.ordering);
  report.order_exact = false;
  if (settings.ordering != Ordering::MeshOrder) throw std::logic_error("ordering not built yet");
  return report;
}

void FrameRenderer::record(VkCommandBuffer cmd, const Camera& camera, const FrameSettings& settings, vk::GpuTimer& timer) {
  interval_.record(cmd, mesh_, targets_, camera, settings.resolve, timer, orderings_->order);
}

OffscreenFrame FrameRenderer::render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent) {
  resize(extent);
  OffscreenFrame frame;
  frame.report = prepare(camera, settings);
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    offscreen_timer_.reset(cmd);
    record(cmd, camera, settings, offscreen_timer_);
  });
  frame.width = extent.width;
  frame.height = extent.height;
  const size_t pixels = size_t(extent.width) * extent.height;
  frame.quantity.resize(pixels);
  frame.display.resize(pixels * 4);
  vk::read_image(device_, targets_.quantity, sizeof(float), std::as_writable_bytes(std::span(frame.quantity)));
  vk::read_image(device_, targets_.display, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.display)));
  if (settings.resolve.quantity == volume::Quantity::Color) {
    frame.emission.resize(pixels * 4);
    vk::read_image(device_, targets_.emission, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.emission)));
  }
  frame.passes = offscreen_timer_.read();
  return frame;
}

}  // namespace prismoid::frame
