#include "renderer/vk/frame_submission.hpp"

#include "renderer/vk/error.hpp"

namespace prismoid::vk {

FrameResources::FrameResources(const Device& d)
    : device(d), image_available(create_semaphore(d)), in_flight(create_fence(d, true)) {
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = d.command_pool();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(d.get(), &alloc, &cmd), "vkAllocateCommandBuffers");
}

FrameResources::~FrameResources() {
  device.wait_idle();
  vkFreeCommandBuffers(device.get(), device.command_pool(), 1, &cmd);
}

void submit_frame(const Device& device, VkCommandBuffer cmd, VkSemaphore acquired, VkSemaphore done, VkFence fence) {
  VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.waitSemaphoreCount = 1;
  submit.pWaitSemaphores = &acquired;
  submit.pWaitDstStageMask = &wait_stage;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  submit.signalSemaphoreCount = 1;
  submit.pSignalSemaphores = &done;
  check(vkQueueSubmit(device.queue(), 1, &submit, fence), "vkQueueSubmit");
}

}  // namespace prismoid::vk
