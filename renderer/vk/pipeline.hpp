#pragma once
// Shader modules, layouts and pipelines. Pipelines use dynamic rendering (no render passes).
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <string_view>
#include <vector>
#include <vulkan/vulkan.h>

#include "renderer/vk/handle.hpp"

namespace prismoid::vk {

class Device;

UniqueShaderModule create_shader_module(const Device& device, std::span<const uint32_t> spirv);

struct DescriptorBinding {
  uint32_t binding;
  VkDescriptorType type;
  VkShaderStageFlags stages;
};
UniqueDescriptorSetLayout create_descriptor_set_layout(const Device& device, std::span<const DescriptorBinding> bindings);

UniquePipelineLayout create_pipeline_layout(const Device& device, std::span<const VkDescriptorSetLayout> sets,
                                            std::span<const VkPushConstantRange> push_constants);

enum class BlendMode { None, Additive, FrontToBack };

struct MeshPipelineDesc {
  std::string_view task_shader;  // name in shaders/ or empty
  std::string_view mesh_shader;
  std::string_view fragment_shader;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::vector<VkFormat> color_formats;
  BlendMode blend = BlendMode::None;
  // A depth attachment of this format, tested with depth_compare and written, when defined.
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  VkCompareOp depth_compare = VK_COMPARE_OP_LESS;
};
UniquePipeline create_mesh_pipeline(const Device& device, const MeshPipelineDesc& desc);

UniquePipeline create_compute_pipeline(const Device& device, std::string_view shader, VkPipelineLayout layout);

// What the mesh and vertex pipelines have in common, for their builders (create_mesh_pipeline,
// create_vertex_pipeline): filled, unculled triangles, one sample, dynamic viewport and
// scissor, dynamic rendering into these formats. Each builder says its stages, its vertex
// input (none for mesh shaders), its depth test and its blending.
struct GraphicsPipelineParts {
  std::vector<std::pair<std::string_view, VkShaderStageFlagBits>> stages;  // shader names; empty ones left out
  const VkPipelineVertexInputStateCreateInfo* vertex_input = nullptr;
  const VkPipelineInputAssemblyStateCreateInfo* input_assembly = nullptr;
  VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  std::vector<VkPipelineColorBlendAttachmentState> attachments;  // one per colour format
  std::vector<VkFormat> color_formats;
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::string name;  // for the error message
};
UniquePipeline create_graphics_pipeline(const Device& device, const GraphicsPipelineParts& parts);

// A descriptor pool sized for `sets` sets of the given bindings, and one set from it.
struct DescriptorSet {
  UniqueDescriptorPool pool;
  VkDescriptorSet set = VK_NULL_HANDLE;
};
DescriptorSet allocate_descriptor_set(const Device& device, VkDescriptorSetLayout layout,
                                      std::span<const DescriptorBinding> bindings);

// Writes to one binding of a descriptor set.
void write_buffer_descriptor(const Device& device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                             VkBuffer buffer);
void write_storage_image_descriptor(const Device& device, VkDescriptorSet set, uint32_t binding, VkImageView view);

}  // namespace prismoid::vk
