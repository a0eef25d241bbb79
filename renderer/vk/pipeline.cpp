#include "renderer/vk/pipeline.hpp"

#include <string>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "shaders/registry.hpp"

namespace prismoid::vk {

UniqueShaderModule create_shader_module(const Device& device, std::span<const uint32_t> spirv) {
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = spirv.size_bytes();
  info.pCode = spirv.data();
  VkShaderModule module;
  check(vkCreateShaderModule(device.get(), &info, nullptr, &module), "vkCreateShaderModule");
  return UniqueShaderModule(device.get(), module);
}

UniqueDescriptorSetLayout create_descriptor_set_layout(const Device& device, std::span<const DescriptorBinding> bindings) {
  std::vector<VkDescriptorSetLayoutBinding> list;
  for (const auto& b : bindings) list.push_back({b.binding, b.type, 1, b.stages, nullptr});
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.bindingCount = static_cast<uint32_t>(list.size());
  info.pBindings = list.data();
  VkDescriptorSetLayout layout;
  check(vkCreateDescriptorSetLayout(device.get(), &info, nullptr, &layout), "vkCreateDescriptorSetLayout");
  return UniqueDescriptorSetLayout(device.get(), layout);
}

UniquePipelineLayout create_pipeline_layout(const Device& device, std::span<const VkDescriptorSetLayout> sets,
                                            std::span<const VkPushConstantRange> push_constants) {
  VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  info.setLayoutCount = static_cast<uint32_t>(sets.size());
  info.pSetLayouts = sets.data();
  info.pushConstantRangeCount = static_cast<uint32_t>(push_constants.size());
  info.pPushConstantRanges = push_constants.data();
  VkPipelineLayout layout;
  check(vkCreatePipelineLayout(device.get(), &info, nullptr, &layout), "vkCreatePipelineLayout");
  return UniquePipelineLayout(device.get(), layout);
}

UniquePipeline create_graphics_pipeline(const Device& device, const GraphicsPipelineParts& parts) {
  std::vector<UniqueShaderModule> modules;
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  for (const auto& [name, stage] : parts.stages) {
    if (name.empty()) continue;
    modules.push_back(create_shader_module(device, shaders::spirv(name)));
    VkPipelineShaderStageCreateInfo s{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    s.stage = stage;
    s.module = modules.back().get();
    s.pName = "main";
    stages.push_back(s);
  }
  VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  viewport.viewportCount = 1;
  viewport.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  raster.polygonMode = VK_POLYGON_MODE_FILL;
  raster.cullMode = VK_CULL_MODE_NONE;
  raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  raster.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  blend.attachmentCount = static_cast<uint32_t>(parts.attachments.size());
  blend.pAttachments = parts.attachments.data();

  VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
  dynamic.dynamicStateCount = 2;
  dynamic.pDynamicStates = dynamic_states;

  VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
  rendering.colorAttachmentCount = static_cast<uint32_t>(parts.color_formats.size());
  rendering.pColorAttachmentFormats = parts.color_formats.data();
  rendering.depthAttachmentFormat = parts.depth_format;

  VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  info.pNext = &rendering;
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.pVertexInputState = parts.vertex_input;
  info.pInputAssemblyState = parts.input_assembly;
  info.pViewportState = &viewport;
  info.pRasterizationState = &raster;
  info.pMultisampleState = &multisample;
  info.pDepthStencilState = &parts.depth;
  info.pColorBlendState = &blend;
  info.pDynamicState = &dynamic;
  info.layout = parts.layout;
  VkPipeline pipeline;
  check(vkCreateGraphicsPipelines(device.get(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
        ("vkCreateGraphicsPipelines (" + parts.name + ")").c_str());
  return UniquePipeline(device.get(), pipeline);
}

UniquePipeline create_mesh_pipeline(const Device& device, const MeshPipelineDesc& desc) {
  if (!device.capabilities().mesh_shader)
    throw NoSuitableDevice(device.capabilities().name + " has no mesh shaders, which volume rendering needs");
  GraphicsPipelineParts parts;
  parts.stages = {{desc.task_shader, VK_SHADER_STAGE_TASK_BIT_EXT},
                  {desc.mesh_shader, VK_SHADER_STAGE_MESH_BIT_EXT},
                  {desc.fragment_shader, VK_SHADER_STAGE_FRAGMENT_BIT}};
  if (desc.depth_format != VK_FORMAT_UNDEFINED) {
    parts.depth.depthTestEnable = VK_TRUE;
    parts.depth.depthWriteEnable = VK_TRUE;
    parts.depth.depthCompareOp = desc.depth_compare;
  }
  parts.attachments.resize(desc.color_formats.size());
  for (auto& a : parts.attachments) {
    a.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    if (desc.blend == BlendMode::Additive) {
      a.blendEnable = VK_TRUE;
      a.srcColorBlendFactor = VK_BLEND_FACTOR_ONE;
      a.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
      a.colorBlendOp = VK_BLEND_OP_ADD;
      a.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      a.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      a.alphaBlendOp = VK_BLEND_OP_ADD;
    } else if (desc.blend == BlendMode::FrontToBack) {
      // Premultiplied colour and alpha, nearest first: dst += (1 - dst.alpha) * src.
      a.blendEnable = VK_TRUE;
      a.srcColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_DST_ALPHA;
      a.dstColorBlendFactor = VK_BLEND_FACTOR_ONE;
      a.colorBlendOp = VK_BLEND_OP_ADD;
      a.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_DST_ALPHA;
      a.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
      a.alphaBlendOp = VK_BLEND_OP_ADD;
    }
  }
  parts.color_formats = desc.color_formats;
  parts.depth_format = desc.depth_format;
  parts.layout = desc.layout;
  parts.name = std::string(desc.mesh_shader);
  return create_graphics_pipeline(device, parts);
}

UniquePipeline create_compute_pipeline(const Device& device, std::string_view shader, VkPipelineLayout layout) {
  UniqueShaderModule module = create_shader_module(device, shaders::spirv(shader));
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module.get();
  info.stage.pName = "main";
  info.layout = layout;
  VkPipeline pipeline;
  check(vkCreateComputePipelines(device.get(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
        ("vkCreateComputePipelines (" + std::string(shader) + ")").c_str());
  return UniquePipeline(device.get(), pipeline);
}

DescriptorSet allocate_descriptor_set(const Device& device, VkDescriptorSetLayout layout,
                                      std::span<const DescriptorBinding> bindings) {
  std::vector<VkDescriptorPoolSize> sizes;
  for (const auto& b : bindings) sizes.push_back({b.type, 1});
  VkDescriptorPoolCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  info.maxSets = 1;
  info.poolSizeCount = static_cast<uint32_t>(sizes.size());
  info.pPoolSizes = sizes.data();
  VkDescriptorPool pool;
  check(vkCreateDescriptorPool(device.get(), &info, nullptr, &pool), "vkCreateDescriptorPool");
  DescriptorSet result;
  result.pool = UniqueDescriptorPool(device.get(), pool);
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = pool;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout;
  check(vkAllocateDescriptorSets(device.get(), &alloc, &result.set), "vkAllocateDescriptorSets");
  return result;
}

void write_buffer_descriptor(const Device& device, VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                             VkBuffer buffer) {
  VkDescriptorBufferInfo info{buffer, 0, VK_WHOLE_SIZE};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = type;
  write.pBufferInfo = &info;
  vkUpdateDescriptorSets(device.get(), 1, &write, 0, nullptr);
}

void write_storage_image_descriptor(const Device& device, VkDescriptorSet set, uint32_t binding, VkImageView view) {
  VkDescriptorImageInfo info{VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  write.pImageInfo = &info;
  vkUpdateDescriptorSets(device.get(), 1, &write, 0, nullptr);
}

}  // namespace prismoid::vk
