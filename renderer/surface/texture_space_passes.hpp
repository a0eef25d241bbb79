#pragma once
// Recording steps the texture-space backends (Htex, texel shading) share: the depth pre-pass
// followed by an EQUAL-tested draw whose fragment shader runs once per visible pixel (marking
// or queueing), the full-screen gather into the colour target, and reading a device buffer
// back. Each backend keeps its own pipelines, descriptor set and push constants.
#include <cstddef>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/vk/handle.hpp"
#include "renderer/vk/memory.hpp"

namespace prismoid::surface {

inline constexpr VkFormat kTextureSpaceColorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
inline constexpr VkFormat kTextureSpaceDepthFormat = VK_FORMAT_D32_SFLOAT;

// What a draw binds: pipeline layout, descriptor set 0 and the push constants.
struct PassBinding {
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkDescriptorSet set = VK_NULL_HANDLE;
  VkShaderStageFlags push_stages = 0;
  std::span<const std::byte> push;
};

// Clears `depth` and draws the scene's triangles twice: with `depth_pipeline` (writes depth),
// then with `visible_pipeline` (EQUAL test, no depth writes).
void record_depth_then_visible(VkCommandBuffer cmd, const GpuSurfaceScene& scene, const vk::Image& depth, VkExtent2D extent,
                               VkPipeline depth_pipeline, VkPipeline visible_pipeline, const PassBinding& binding);

// One full-screen triangle with `pipeline` into `color` (every pixel written); leaves `color`
// in TRANSFER_SRC_OPTIMAL.
void record_fullscreen(VkCommandBuffer cmd, const vk::Image& color, VkExtent2D extent, VkPipeline pipeline, const PassBinding& binding);

// The pipelines of a pre-pass / EQUAL-draw pair (the depth pipeline uses surface/depth.vert).
struct DepthThenVisiblePipelines {
  vk::UniquePipeline depth, visible;
};
DepthThenVisiblePipelines create_depth_then_visible(const vk::Device& device, VkPipelineLayout layout, const char* visible_fragment_shader);
// A full-screen pipeline (surface/sky.vert) writing kTextureSpaceColorFormat.
vk::UniquePipeline create_fullscreen(const vk::Device& device, VkPipelineLayout layout, const char* fragment_shader);

// Copies a device buffer to the host (waits for the device).
std::vector<std::byte> read_device_buffer(const vk::Device& device, const vk::Buffer& buffer);

}  // namespace prismoid::surface
