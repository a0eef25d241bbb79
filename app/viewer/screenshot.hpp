#pragma once
// Screenshots of what the window shows: the swapchain image after the UI was drawn into it,
// copied to a host buffer in the frame's own command buffer and written as PNG once the
// frame's fence has signalled.
#include <optional>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

#include "io/image_io.hpp"
#include "renderer/vk/memory.hpp"

namespace prismoid::app {

class SwapchainCapture {
 public:
  explicit SwapchainCapture(const vk::Device& device) : device_(device) {}

  // Records the copy of `image` (PRESENT_SRC layout, the UI drawn) into a host buffer; the
  // image goes back to PRESENT_SRC. `path` is written by finish().
  void record(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, VkFormat format, std::string path);
  bool pending() const { return !path_.empty(); }
  // After the recorded frame has finished: writes the PNG through app/common/output_files.hpp (never
  // over one of `inputs`), returns its path (nullopt if none was pending).
  std::optional<std::string> finish(const std::vector<std::string>& inputs);

 private:
  const vk::Device& device_;
  vk::Buffer buffer_;
  VkExtent2D extent_{};
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  std::string path_;
};

// 8-bit swapchain pixels (BGRA or RGBA order, sRGB-encoded as the screen shows them) as a
// linear RGBA float image, the form io::write_png encodes back to the same bytes.
io::FloatImage swapchain_pixels(const std::byte* bytes, VkExtent2D extent, VkFormat format);

}  // namespace prismoid::app
