#pragma once
// Reading a depth buffer back: the volume's rays end at opaque surfaces (issue "A volume inside
// its geometry"), whose depth the surface passes leave in a D32 attachment.
#include <vector>

#include <vulkan/vulkan.h>

#include "renderer/vk/device.hpp"
#include "renderer/vk/memory.hpp"

namespace prismoid::vk {

// The depth aspect of a VK_FORMAT_D32_SFLOAT image as one float per pixel, row 0 at the top.
// `layout`: the image's layout, turned to TRANSFER_SRC after every earlier depth write and back
// after the copy. The image needs VK_IMAGE_USAGE_TRANSFER_SRC_BIT.
std::vector<float> read_depth(const Device& device, const Image& image,
                              VkImageLayout layout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);

}  // namespace prismoid::vk
