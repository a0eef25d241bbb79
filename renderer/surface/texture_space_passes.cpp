#include "renderer/surface/texture_space_passes.hpp"

#include <cstring>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/graphics_pipeline.hpp"
#include "renderer/vk/pipeline.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

void bind_graphics(VkCommandBuffer cmd, VkPipeline pipeline, const PassBinding& b) {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline);
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, b.layout, 0, 1, &b.set, 0, nullptr);
  if (!b.push.empty()) vkCmdPushConstants(cmd, b.layout, b.push_stages, 0, uint32_t(b.push.size()), b.push.data());
}

void set_viewport(VkCommandBuffer cmd, VkExtent2D e) {
  const VkViewport viewport{0.0f, 0.0f, float(e.width), float(e.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, e};
  vkCmdSetViewport(cmd, 0, 1, &viewport);
  vkCmdSetScissor(cmd, 0, 1, &scissor);
}

std::string texture_space_device_problem(const vk::Device& device, const std::string& backend) {
  const auto& caps = device.capabilities();
  if (!caps.geometry_shader) return caps.name + " cannot read gl_PrimitiveID in fragment shaders (no geometryShader feature)";
  if (!caps.fragment_stores) return caps.name + " cannot write storage buffers from fragment shaders";
  if (!device.ray_tracing_enabled()) return caps.name + " has no ray tracing enabled (" + backend + "'s shading pass is a ray-generation shader)";
  if (!device.cmd_trace_rays_indirect)
    return caps.name + " cannot trace rays with GPU-written launch sizes (rayTracingPipelineTraceRaysIndirect)";
  if (!(device.format_properties(kTextureSpaceColorFormat).optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT))
    return caps.name + " cannot render to R32G32B32A32_SFLOAT images";
  return {};
}

TextureSpaceTargets create_texture_space_targets(const vk::Device& device, VkExtent2D extent) {
  if (extent.width == 0 || extent.height == 0) throw InputError(setting("size"), "the image size must be positive");
  TextureSpaceTargets t;
  t.extent = extent;
  t.color = vk::Image(device, extent, kTextureSpaceColorFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  // Readable: a volume's rays end at the surfaces (renderer/mixed).
  t.depth = vk::Image(device, extent, kTextureSpaceDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.visibility = vk::Buffer(device, VkDeviceSize(extent.width) * extent.height * 16,
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                            vk::MemoryUse::DeviceLocal);
  return t;
}

void read_texture_space_image(const vk::Device& device, const TextureSpaceTargets& targets, vk::GpuTimer& timer, TextureSpaceImage& image) {
  image.width = targets.extent.width;
  image.height = targets.extent.height;
  const size_t pixels = size_t(image.width) * image.height;
  image.rgba.resize(pixels * 4);
  vk::read_image(device, targets.color, sizeof(float) * 4, std::as_writable_bytes(std::span(image.rgba)));
  const std::vector<std::byte> vis = read_device_buffer(device, targets.visibility);
  image.visibility.resize(pixels);
  std::memcpy(image.visibility.data(), vis.data(), pixels * sizeof(glm::uvec4));
  image.passes = timer.read();
}

void SceneSetBinding::update(const vk::Device& device, VkDescriptorSet set, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                             const vk::Buffer& visibility, uint32_t visibility_binding) {
  const bool new_scene = scene_ != buffer_key(scene);
  if (new_scene) {
    write_scene_descriptors(device, set, scene, true);
    scene_ = buffer_key(scene);
  }
  if (new_scene || tlas_ != tlas) {
    rt::write_tlas_descriptor(device, set, PRISMOID_SURFACE_BINDING_TLAS, tlas);
    tlas_ = tlas;
  }
  if (visibility_ != visibility.serial()) {
    vk::write_buffer_descriptor(device, set, visibility_binding, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, visibility.get());
    visibility_ = visibility.serial();
  }
}

void record_indirect_shading(VkCommandBuffer cmd, vk::GpuTimer& timer, const rt::RayTracingPipeline& pipeline, uint32_t raygen,
                             const PassBinding& binding, VkDeviceAddress launch) {
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                     VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  {
    vk::ScopedPass pass(timer, cmd, "shading");
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, pipeline.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, binding.layout, 0, 1, &binding.set, 0, nullptr);
    if (!binding.push.empty()) vkCmdPushConstants(cmd, binding.layout, binding.push_stages, 0, uint32_t(binding.push.size()), binding.push.data());
    pipeline.trace_indirect(cmd, raygen, launch);
  }
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

void record_state_readback(VkCommandBuffer cmd, const vk::Buffer& state, const vk::Buffer& readback, VkDeviceSize bytes) {
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR,
                     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  const VkBufferCopy copy{0, 0, bytes};
  vkCmdCopyBuffer(cmd, state.get(), readback.get(), 1, &copy);
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

void record_depth_then_visible(VkCommandBuffer cmd, const GpuSurfaceScene& scene, const vk::Image& depth_image, VkExtent2D e,
                               VkPipeline depth_pipeline, VkPipeline visible_pipeline, const PassBinding& binding) {
  constexpr VkPipelineStageFlags2 kTests = VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  constexpr VkAccessFlags2 kDepthAccess = VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
  const VkDeviceSize zero = 0;
  const VkBuffer positions = scene.positions.get();
  const uint32_t index_count = scene.triangle_count * 3;
  vk::image_barrier(cmd, depth_image.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, kTests, kDepthAccess, kTests,
                    kDepthAccess, VK_IMAGE_ASPECT_DEPTH_BIT);
  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = depth_image.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  depth.clearValue.depthStencil = {0.0f, 0};  // reversed z: 0 is infinitely far
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = {{0, 0}, e};
  rendering.layerCount = 1;
  rendering.pDepthAttachment = &depth;
  for (int draw = 0; draw < 2; ++draw) {
    if (draw == 1) {
      vk::image_barrier(cmd, depth_image.get(), VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, kTests,
                        VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, kTests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                        VK_IMAGE_ASPECT_DEPTH_BIT);
      depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
      depth.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
    }
    vkCmdBeginRendering(cmd, &rendering);
    set_viewport(cmd, e);
    if (index_count > 0) {
      bind_graphics(cmd, draw == 0 ? depth_pipeline : visible_pipeline, binding);
      vkCmdBindVertexBuffers(cmd, 0, 1, &positions, &zero);
      vkCmdBindIndexBuffer(cmd, scene.indices.get(), 0, VK_INDEX_TYPE_UINT32);
      vkCmdDrawIndexed(cmd, index_count, 1, 0, 0, 0);
    }
    vkCmdEndRendering(cmd);
  }
}

void record_fullscreen(VkCommandBuffer cmd, const vk::Image& color_image, VkExtent2D e, VkPipeline pipeline, const PassBinding& binding) {
  vk::image_barrier(cmd, color_image.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_NONE,
                    VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
  VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  color.imageView = color_image.view();
  color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
  color.loadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;  // every pixel is written
  color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = {{0, 0}, e};
  rendering.layerCount = 1;
  rendering.colorAttachmentCount = 1;
  rendering.pColorAttachments = &color;
  vkCmdBeginRendering(cmd, &rendering);
  set_viewport(cmd, e);
  bind_graphics(cmd, pipeline, binding);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
  vk::image_barrier(cmd, color_image.get(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT);
}

DepthThenVisiblePipelines create_depth_then_visible(const vk::Device& device, VkPipelineLayout layout, const char* visible_fragment_shader) {
  vk::VertexPipelineDesc depth;
  depth.vertex_shader = "surface/depth.vert";
  depth.layout = layout;
  depth.bindings = {{0, sizeof(float) * 3, VK_VERTEX_INPUT_RATE_VERTEX}};
  depth.attributes = {{PRISMOID_SURFACE_VERTEX_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
  depth.depth_format = kTextureSpaceDepthFormat;
  depth.depth_compare = VK_COMPARE_OP_GREATER;  // reversed z
  depth.depth_write = true;
  DepthThenVisiblePipelines p;
  p.depth = vk::create_vertex_pipeline(device, depth);
  vk::VertexPipelineDesc visible = depth;
  visible.fragment_shader = visible_fragment_shader;
  visible.depth_compare = VK_COMPARE_OP_EQUAL;  // only the surface the pre-pass kept
  visible.depth_write = false;
  p.visible = vk::create_vertex_pipeline(device, visible);
  return p;
}

vk::UniquePipeline create_fullscreen(const vk::Device& device, VkPipelineLayout layout, const char* fragment_shader) {
  vk::VertexPipelineDesc gather;
  gather.vertex_shader = "surface/sky.vert";  // one triangle covering the viewport
  gather.fragment_shader = fragment_shader;
  gather.layout = layout;
  gather.color_formats = {kTextureSpaceColorFormat};
  return vk::create_vertex_pipeline(device, gather);
}

std::vector<std::byte> read_device_buffer(const vk::Device& device, const vk::Buffer& buffer) {
  vk::Buffer staging(device, buffer.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                       VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkBufferCopy copy{0, 0, buffer.size()};
    vkCmdCopyBuffer(cmd, buffer.get(), staging.get(), 1, &copy);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  });
  std::vector<std::byte> out(buffer.size());
  std::memcpy(out.data(), staging.mapped(), out.size());
  return out;
}

}  // namespace prismoid::surface
