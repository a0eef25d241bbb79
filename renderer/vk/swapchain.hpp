#pragma once
// A swapchain over a surface the caller owns; recreated on resize. Images are written by
// transfer (the frame's display image is blitted into them), may be drawn over (the UI) and
// read back (screenshots), then presented.
#include <optional>
#include <vector>
#include <vulkan/vulkan.h>

#include "renderer/vk/handle.hpp"

namespace prismoid::vk {

class Device;

class Swapchain {
 public:
  Swapchain(const Device& device, VkSurfaceKHR surface, VkExtent2D framebuffer_size);

  // Rebuilds for a new framebuffer size (after a resize or an out-of-date result).
  void recreate(VkExtent2D framebuffer_size);

  // Index of the next image, or nullopt when the swapchain must be recreated first.
  std::optional<uint32_t> acquire(VkSemaphore signal);
  // Returns false when the swapchain is out of date or suboptimal and should be recreated.
  bool present(uint32_t index, VkSemaphore wait);

  VkExtent2D extent() const { return extent_; }
  VkFormat format() const { return format_; }
  VkImage image(uint32_t index) const { return images_[index]; }
  uint32_t image_count() const { return static_cast<uint32_t>(images_.size()); }
  // One semaphore per image, signalled when rendering into it is done (waited by present).
  VkSemaphore render_finished(uint32_t index) const { return render_finished_[index].get(); }

 private:
  const Device& device_;
  VkSurfaceKHR surface_;
  UniqueSwapchain swapchain_;
  std::vector<VkImage> images_;
  std::vector<UniqueSemaphore> render_finished_;
  VkExtent2D extent_{};
  VkFormat format_ = VK_FORMAT_UNDEFINED;
};

UniqueSemaphore create_semaphore(const Device& device);
UniqueFence create_fence(const Device& device, bool signaled);

}  // namespace prismoid::vk
