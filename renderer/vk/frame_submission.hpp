#pragma once
// Submitting a presented frame: what every window's frame loop needs from Vulkan, beside the
// swapchain (swapchain.hpp). One frame in flight at a time.
#include <vulkan/vulkan.h>

#include "renderer/vk/device.hpp"
#include "renderer/vk/handle.hpp"
#include "renderer/vk/swapchain.hpp"

namespace prismoid::vk {

// One frame in flight: the semaphore the acquired image signals, the fence of the frame's
// submission (created signalled) and its command buffer (freed once the device is idle).
struct FrameResources {
  explicit FrameResources(const Device& device);
  ~FrameResources();
  FrameResources(const FrameResources&) = delete;
  FrameResources& operator=(const FrameResources&) = delete;
  const Device& device;
  UniqueSemaphore image_available;
  UniqueFence in_flight;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
};

// Submits `cmd`: waits for the acquired image before the transfer that writes it (the blit of
// the frame into the swapchain image); signals `done` for presentation and `fence` when finished.
void submit_frame(const Device& device, VkCommandBuffer cmd, VkSemaphore acquired, VkSemaphore done, VkFence fence);

}  // namespace prismoid::vk
