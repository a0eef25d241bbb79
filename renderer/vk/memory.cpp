#include "renderer/vk/memory.hpp"

#include <atomic>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"

namespace prismoid::vk {

uint64_t next_resource_serial() {
  static std::atomic<uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

Buffer::Buffer(const Device& device, VkDeviceSize size, VkBufferUsageFlags usage, MemoryUse use)
    : serial_(next_resource_serial()), size_(size), device_(device.get()) {
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size > 0 ? size : 16;  // zero-sized buffers are invalid; empty meshes get a stub
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  VkBuffer buffer;
  check(vkCreateBuffer(device_, &info, nullptr, &buffer), "vkCreateBuffer");
  buffer_ = UniqueBuffer(device_, buffer);

  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, buffer, &req);
  VkMemoryPropertyFlags flags = use == MemoryUse::HostVisible
                                    ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                    : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = device.memory_type(req.memoryTypeBits, flags);
  VkMemoryAllocateFlagsInfo alloc_flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  alloc_flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  addressable_ = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0;
  if (addressable_) alloc.pNext = &alloc_flags;
  VkDeviceMemory memory;
  check(vkAllocateMemory(device_, &alloc, nullptr, &memory), "vkAllocateMemory (buffer)");
  memory_ = UniqueMemory(device_, memory);
  check(vkBindBufferMemory(device_, buffer, memory, 0), "vkBindBufferMemory");
  if (use == MemoryUse::HostVisible) {
    void* ptr = nullptr;
    check(vkMapMemory(device_, memory, 0, VK_WHOLE_SIZE, 0, &ptr), "vkMapMemory");
    mapped_ = static_cast<std::byte*>(ptr);
  }
}

Buffer::~Buffer() {
  if (mapped_ && memory_) vkUnmapMemory(device_, memory_.get());
}

void Buffer::write(std::span<const std::byte> bytes, VkDeviceSize offset) {
  if (!mapped_) throw std::logic_error("Buffer::write on a buffer that is not host-visible");
  if (offset + bytes.size() > size_) throw std::out_of_range("Buffer::write past the end of the buffer");
  std::memcpy(mapped_ + offset, bytes.data(), bytes.size());
}

VkDeviceAddress Buffer::device_address() const {
  if (!addressable_) throw std::logic_error("Buffer::device_address on a buffer made without SHADER_DEVICE_ADDRESS usage");
  VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  info.buffer = buffer_.get();
  return vkGetBufferDeviceAddress(device_, &info);
}

Buffer upload_buffer(const Device& device, std::span<const std::byte> bytes, VkBufferUsageFlags usage) {
  Buffer result(device, bytes.size(), usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::DeviceLocal);
  if (bytes.empty()) return result;
  Buffer staging(device, bytes.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::HostVisible);
  staging.write(bytes);
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    VkBufferCopy region{0, 0, bytes.size()};
    vkCmdCopyBuffer(cmd, staging.get(), result.get(), 1, &region);
  });
  return result;
}

VkImageAspectFlags aspect_of(VkFormat format) {
  switch (format) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
    case VK_FORMAT_D32_SFLOAT: return VK_IMAGE_ASPECT_DEPTH_BIT;
    default: return VK_IMAGE_ASPECT_COLOR_BIT;
  }
}

Image::Image(const Device& device, VkExtent2D extent, VkFormat format, VkImageUsageFlags usage)
    : serial_(next_resource_serial()), format_(format), extent_(extent) {
  VkDevice d = device.get();
  VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {extent.width, extent.height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImage image;
  check(vkCreateImage(d, &info, nullptr, &image), "vkCreateImage");
  image_ = UniqueImage(d, image);

  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(d, image, &req);
  VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  VkDeviceMemory memory;
  check(vkAllocateMemory(d, &alloc, nullptr, &memory), "vkAllocateMemory (image)");
  memory_ = UniqueMemory(d, memory);
  check(vkBindImageMemory(d, image, memory, 0), "vkBindImageMemory");

  VkImageViewCreateInfo view_info{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  view_info.image = image;
  view_info.viewType = VK_IMAGE_VIEW_TYPE_2D;
  view_info.format = format;
  view_info.subresourceRange = {aspect_of(format), 0, 1, 0, 1};
  VkImageView view;
  check(vkCreateImageView(d, &view_info, nullptr, &view), "vkCreateImageView");
  view_ = UniqueImageView(d, view);
}

void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
  barrier.srcStageMask = src_stage;
  barrier.srcAccessMask = src_access;
  barrier.dstStageMask = dst_stage;
  barrier.dstAccessMask = dst_access;
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.memoryBarrierCount = 1;
  dep.pMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void buffer_barrier(VkCommandBuffer cmd, std::initializer_list<VkBuffer> buffers, VkPipelineStageFlags2 src_stage,
                    VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access) {
  std::vector<VkBufferMemoryBarrier2> barriers;
  for (VkBuffer buffer : buffers) {
    VkBufferMemoryBarrier2 b{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
    b.srcStageMask = src_stage;
    b.srcAccessMask = src_access;
    b.dstStageMask = dst_stage;
    b.dstAccessMask = dst_access;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.buffer = buffer;
    b.offset = 0;
    b.size = VK_WHOLE_SIZE;
    barriers.push_back(b);
  }
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.bufferMemoryBarrierCount = static_cast<uint32_t>(barriers.size());
  dep.pBufferMemoryBarriers = barriers.data();
  vkCmdPipelineBarrier2(cmd, &dep);
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                   VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                   VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access, VkImageAspectFlags aspect) {
  VkImageMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  barrier.srcStageMask = src_stage;
  barrier.srcAccessMask = src_access;
  barrier.dstStageMask = dst_stage;
  barrier.dstAccessMask = dst_access;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {aspect, 0, 1, 0, 1};
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = 1;
  dep.pImageMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd, &dep);
}

void read_image(const Device& device, const Image& image, size_t bytes_per_pixel, std::span<std::byte> out, VkImageLayout layout) {
  VkExtent2D e = image.extent();
  VkDeviceSize size = VkDeviceSize(e.width) * e.height * bytes_per_pixel;
  if (out.size() != size) throw std::invalid_argument("read_image: output span has the wrong size");
  Buffer staging(device, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUse::HostVisible);
  const bool turn = layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    if (turn)
      image_barrier(cmd, image.get(), layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                    VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {e.width, e.height, 1};
    vkCmdCopyImageToBuffer(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging.get(), 1, &region);
    if (turn)
      image_barrier(cmd, image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                    VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  std::memcpy(out.data(), staging.mapped(), size);
}

}  // namespace prismoid::vk
