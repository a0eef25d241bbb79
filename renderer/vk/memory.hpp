#pragma once
// Buffers and images with their own memory. Host-visible buffers stay mapped.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <vulkan/vulkan.h>

#include "renderer/vk/handle.hpp"

namespace prismoid::vk {

class Device;

enum class MemoryUse { DeviceLocal, HostVisible };

// A number no buffer or image made before in this process has had (0: none made). Descriptor
// caches compare serials, not handles or addresses: once an object is destroyed, Vulkan may hand
// its handle to the next one and the allocator its address to the next scene, and a cache keyed
// by those would skip writing descriptors that still name the destroyed object.
uint64_t next_resource_serial();

class Buffer {
 public:
  Buffer() = default;
  Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use);
  Buffer(Buffer&&) noexcept = default;
  Buffer& operator=(Buffer&&) noexcept = default;
  ~Buffer();

  VkBuffer get() const { return buffer_.get(); }
  VkDeviceSize size() const { return size_; }
  // Host-visible buffers only: the mapped bytes.
  std::byte* mapped() const { return mapped_; }
  void write(std::span<const std::byte> bytes, VkDeviceSize offset = 0);
  // Buffers made with VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT only (their memory is then
  // allocated with VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT): the buffer's GPU address.
  VkDeviceAddress device_address() const;
  uint64_t serial() const { return serial_; }

 private:
  UniqueMemory memory_;  // declared first so the buffer is destroyed before its memory
  UniqueBuffer buffer_;
  uint64_t serial_ = 0;
  VkDeviceSize size_ = 0;
  std::byte* mapped_ = nullptr;
  VkDevice device_ = VK_NULL_HANDLE;
  bool addressable_ = false;
};

// Creates a device-local buffer holding `bytes` (uploaded through a staging buffer).
Buffer upload_buffer(const Device& device, std::span<const std::byte> bytes, VkBufferUsageFlags usage);

class Image {
 public:
  Image() = default;
  Image(const Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage);
  Image(Image&&) noexcept = default;
  Image& operator=(Image&&) noexcept = default;

  VkImage get() const { return image_.get(); }
  VkImageView view() const { return view_.get(); }
  VkFormat format() const { return format_; }
  VkExtent2D extent() const { return extent_; }
  uint64_t serial() const { return serial_; }

 private:
  uint64_t serial_ = 0;
  UniqueMemory memory_;  // destroyed last: view, then image, then memory
  UniqueImage image_;
  UniqueImageView view_;
  VkFormat format_ = VK_FORMAT_UNDEFINED;
  VkExtent2D extent_{};
};

// The aspect an image of this format has: depth for the depth-only formats, else colour.
VkImageAspectFlags aspect_of(VkFormat format);

// One global memory dependency (synchronization2): every resource, these stages and accesses.
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

// One pipeline barrier on whole buffers (synchronization2).
void buffer_barrier(VkCommandBuffer cmd, std::initializer_list<VkBuffer> buffers, VkPipelineStageFlags2 src_stage,
                    VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access);

// A pipeline barrier on a whole image (synchronization2), colour unless told.
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access,
                   VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT);

// Copies a colour image into host memory, tightly packed. `layout`: the image's layout; one
// other than TRANSFER_SRC_OPTIMAL (a storage image in GENERAL) is turned to it after every earlier
// write, and back after the copy.
void read_image(const Device& device, const Image& image, size_t bytes_per_pixel, std::span<std::byte> out,
                VkImageLayout layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);

}  // namespace prismoid::vk
