#pragma once
// Classic vertex-input graphics pipelines (vertex + optional fragment shader) with dynamic
// rendering: what the raster surface backends draw with. Mesh-shader pipelines are in
// pipeline.hpp.
#include <string_view>
#include <vector>
#include <vulkan/vulkan.h>

#include "renderer/vk/handle.hpp"

namespace prismoid::vk {

class Device;

struct VertexPipelineDesc {
  std::string_view vertex_shader;    // name in shaders/
  std::string_view fragment_shader;  // empty: no fragment stage (a depth-only pass)
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::vector<VkVertexInputBindingDescription> bindings;
  std::vector<VkVertexInputAttributeDescription> attributes;
  std::vector<VkFormat> color_formats;
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  VkCompareOp depth_compare = VK_COMPARE_OP_ALWAYS;
  bool depth_write = false;
};
// Triangle lists, no culling (surfaces are two-sided), one sample per pixel, no blending;
// viewport and scissor are dynamic.
UniquePipeline create_vertex_pipeline(const Device& device, const VertexPipelineDesc& desc);

}  // namespace prismoid::vk
