#include "renderer/vk/swapchain.hpp"

#include <algorithm>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"

namespace prismoid::vk {

UniqueSemaphore create_semaphore(const Device& device) {
  VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VkSemaphore s;
  check(vkCreateSemaphore(device.get(), &info, nullptr, &s), "vkCreateSemaphore");
  return UniqueSemaphore(device.get(), s);
}

UniqueFence create_fence(const Device& device, bool signaled) {
  VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  if (signaled) info.flags = VK_FENCE_CREATE_SIGNALED_BIT;
  VkFence f;
  check(vkCreateFence(device.get(), &info, nullptr, &f), "vkCreateFence");
  return UniqueFence(device.get(), f);
}

Swapchain::Swapchain(const Device& device, VkSurfaceKHR surface, VkExtent2D framebuffer_size)
    : device_(device), surface_(surface) {
  VkBool32 supported = VK_FALSE;
  check(vkGetPhysicalDeviceSurfaceSupportKHR(device.physical(), device.queue_family(), surface, &supported),
        "vkGetPhysicalDeviceSurfaceSupportKHR");
  if (!supported) throw NoSuitableDevice(device.capabilities().name + " cannot present to this window");
  recreate(framebuffer_size);
}

void Swapchain::recreate(VkExtent2D framebuffer_size) {
  device_.wait_idle();
  VkSurfaceCapabilitiesKHR caps;
  check(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(device_.physical(), surface_, &caps), "vkGetPhysicalDeviceSurfaceCapabilitiesKHR");
  // Transfer writes (the frame's display image is blitted in), colour attachment (the UI is
  // drawn over it) and transfer reads (screenshots of what the window shows).
  constexpr VkImageUsageFlags usage =
      VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  if ((caps.supportedUsageFlags & usage) != usage)
    throw NoSuitableDevice("the window surface does not accept transfer writes, transfer reads and drawing");

  uint32_t count = 0;
  check(vkGetPhysicalDeviceSurfaceFormatsKHR(device_.physical(), surface_, &count, nullptr), "vkGetPhysicalDeviceSurfaceFormatsKHR");
  std::vector<VkSurfaceFormatKHR> formats(count);
  check(vkGetPhysicalDeviceSurfaceFormatsKHR(device_.physical(), surface_, &count, formats.data()), "vkGetPhysicalDeviceSurfaceFormatsKHR");
  // An sRGB format, so the blit from the linear display image encodes correctly.
  VkSurfaceFormatKHR chosen = formats.front();
  for (const auto& f : formats)
    if ((f.format == VK_FORMAT_B8G8R8A8_SRGB || f.format == VK_FORMAT_R8G8B8A8_SRGB) &&
        f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR) {
      chosen = f;
      break;
    }
  format_ = chosen.format;

  if (caps.currentExtent.width != UINT32_MAX) {
    extent_ = caps.currentExtent;
  } else {
    extent_.width = std::clamp(framebuffer_size.width, caps.minImageExtent.width, caps.maxImageExtent.width);
    extent_.height = std::clamp(framebuffer_size.height, caps.minImageExtent.height, caps.maxImageExtent.height);
  }
  uint32_t image_count = caps.minImageCount + 1;
  if (caps.maxImageCount > 0) image_count = std::min(image_count, caps.maxImageCount);

  VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
  info.surface = surface_;
  info.minImageCount = image_count;
  info.imageFormat = chosen.format;
  info.imageColorSpace = chosen.colorSpace;
  info.imageExtent = extent_;
  info.imageArrayLayers = 1;
  info.imageUsage = usage;
  info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.preTransform = caps.currentTransform;
  info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
  info.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always available
  info.clipped = VK_TRUE;
  info.oldSwapchain = swapchain_.get();
  VkSwapchainKHR handle;
  check(vkCreateSwapchainKHR(device_.get(), &info, nullptr, &handle), "vkCreateSwapchainKHR");
  swapchain_ = UniqueSwapchain(device_.get(), handle);

  check(vkGetSwapchainImagesKHR(device_.get(), handle, &count, nullptr), "vkGetSwapchainImagesKHR");
  images_.resize(count);
  check(vkGetSwapchainImagesKHR(device_.get(), handle, &count, images_.data()), "vkGetSwapchainImagesKHR");
  render_finished_.clear();
  for (uint32_t i = 0; i < count; ++i) render_finished_.push_back(create_semaphore(device_));
}

std::optional<uint32_t> Swapchain::acquire(VkSemaphore signal) {
  uint32_t index = 0;
  VkResult r = vkAcquireNextImageKHR(device_.get(), swapchain_.get(), UINT64_MAX, signal, VK_NULL_HANDLE, &index);
  if (r == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;
  if (r != VK_SUBOPTIMAL_KHR) check(r, "vkAcquireNextImageKHR");
  return index;
}

bool Swapchain::present(uint32_t index, VkSemaphore wait) {
  VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
  info.waitSemaphoreCount = 1;
  info.pWaitSemaphores = &wait;
  VkSwapchainKHR handle = swapchain_.get();
  info.swapchainCount = 1;
  info.pSwapchains = &handle;
  info.pImageIndices = &index;
  VkResult r = vkQueuePresentKHR(device_.queue(), &info);
  if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) return false;
  check(r, "vkQueuePresentKHR");
  return true;
}

}  // namespace prismoid::vk
