#include "app/viewer/screenshot.hpp"

#include <cmath>
#include <utility>

#include "app/common/output_files.hpp"
#include "renderer/vk/device.hpp"

namespace prismoid::app {

void SwapchainCapture::record(VkCommandBuffer cmd, VkImage image, VkExtent2D extent, VkFormat format, std::string path) {
  const VkDeviceSize bytes = VkDeviceSize(extent.width) * extent.height * 4;
  if (buffer_.size() < bytes) buffer_ = vk::Buffer(device_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  vk::image_barrier(cmd, image, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {extent.width, extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer_.get(), 1, &region);
  vk::image_barrier(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE);
  vk::buffer_barrier(cmd, {buffer_.get()}, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                     VK_ACCESS_2_HOST_READ_BIT);
  extent_ = extent;
  format_ = format;
  path_ = std::move(path);
}

std::optional<std::string> SwapchainCapture::finish(const std::vector<std::string>& inputs) {
  if (path_.empty()) return std::nullopt;
  std::string path = std::exchange(path_, {});
  OutputFiles files;
  for (const std::string& in : inputs) files.input(in);
  files.output(path, "screenshot", {".png"});
  files.write(path, [&](const std::string& file) { io::write_png(file, swapchain_pixels(buffer_.mapped(), extent_, format_)); });
  files.commit();
  return path;
}

io::FloatImage swapchain_pixels(const std::byte* bytes, VkExtent2D extent, VkFormat format) {
  const bool bgr = format == VK_FORMAT_B8G8R8A8_SRGB || format == VK_FORMAT_B8G8R8A8_UNORM;
  io::FloatImage image;
  image.width = extent.width;
  image.height = extent.height;
  image.channels = 4;
  image.pixels.resize(size_t(extent.width) * extent.height * 4);
  float linear[256];
  for (int i = 0; i < 256; ++i) {
    const double c = i / 255.0;
    linear[i] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
  }
  for (size_t p = 0; p < size_t(extent.width) * extent.height; ++p) {
    const auto* px = reinterpret_cast<const uint8_t*>(bytes + 4 * p);
    image.pixels[4 * p + 0] = linear[bgr ? px[2] : px[0]];
    image.pixels[4 * p + 1] = linear[px[1]];
    image.pixels[4 * p + 2] = linear[bgr ? px[0] : px[2]];
    image.pixels[4 * p + 3] = 1.0f;  // the window is opaque
  }
  return image;
}

}  // namespace prismoid::app
