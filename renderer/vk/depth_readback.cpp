#include "renderer/vk/depth_readback.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace prismoid::vk {

std::vector<float> read_depth(const Device& device, const Image& image, VkImageLayout layout) {
  if (image.format() != VK_FORMAT_D32_SFLOAT) throw std::invalid_argument("read_depth: the image is not D32_SFLOAT");
  const VkExtent2D e = image.extent();
  std::vector<float> depth(size_t(e.width) * e.height);
  const VkDeviceSize size = VkDeviceSize(depth.size() * sizeof(float));
  Buffer staging(device, std::max<VkDeviceSize>(size, 4), VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::HostVisible);
  constexpr VkPipelineStageFlags2 kDepthStages = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    image_barrier(cmd, image.get(), layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, kDepthStages,
                  VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                  VK_IMAGE_ASPECT_DEPTH_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1};
    region.imageExtent = {e.width, e.height, 1};
    vkCmdCopyImageToBuffer(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.get(), 1, &region);
    image_barrier(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout, VK_PIPELINE_STAGE_2_COPY_BIT,
                  VK_ACCESS_2_TRANSFER_READ_BIT, kDepthStages,
                  VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  std::memcpy(depth.data(), staging.mapped(), size);
  return depth;
}

}  // namespace prismoid::vk
