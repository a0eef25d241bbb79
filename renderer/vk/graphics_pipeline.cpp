#include "renderer/vk/graphics_pipeline.hpp"

#include <string>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/pipeline.hpp"
#include "shaders/registry.hpp"

namespace prismoid::vk {

UniquePipeline create_vertex_pipeline(const Device& device, const VertexPipelineDesc& desc) {
  GraphicsPipelineParts parts;
  parts.stages = {{desc.vertex_shader, VK_SHADER_STAGE_VERTEX_BIT}, {desc.fragment_shader, VK_SHADER_STAGE_FRAGMENT_BIT}};
  VkPipelineVertexInputStateCreateInfo vertex_input{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  vertex_input.vertexBindingDescriptionCount = static_cast<uint32_t>(desc.bindings.size());
  vertex_input.pVertexBindingDescriptions = desc.bindings.data();
  vertex_input.vertexAttributeDescriptionCount = static_cast<uint32_t>(desc.attributes.size());
  vertex_input.pVertexAttributeDescriptions = desc.attributes.data();
  VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  parts.vertex_input = &vertex_input;
  parts.input_assembly = &assembly;
  if (desc.depth_format != VK_FORMAT_UNDEFINED) {
    parts.depth.depthTestEnable = VK_TRUE;
    parts.depth.depthWriteEnable = desc.depth_write ? VK_TRUE : VK_FALSE;
    parts.depth.depthCompareOp = desc.depth_compare;
  }
  parts.attachments.resize(desc.color_formats.size());
  for (auto& a : parts.attachments)
    a.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  parts.color_formats = desc.color_formats;
  parts.depth_format = desc.depth_format;
  parts.layout = desc.layout;
  parts.name = std::string(desc.vertex_shader) + ", " + std::string(desc.fragment_shader);
  return create_graphics_pipeline(device, parts);
}

}  // namespace prismoid::vk
