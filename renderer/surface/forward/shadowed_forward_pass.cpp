#include "renderer/surface/forward/shadowed_forward_pass.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/surface/view_depth.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/graphics_pipeline.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;
constexpr VkFormat kTriangleFormat = VK_FORMAT_R32_UINT;
constexpr uint32_t kBindingTriangle = PRISMOID_SURFACE_BINDING_BACKEND + 0;
constexpr uint32_t kBindingColor = PRISMOID_SURFACE_BINDING_BACKEND + 1;
constexpr uint32_t kBindingCounter = PRISMOID_SURFACE_BINDING_BACKEND + 2;

std::vector<vk::DescriptorBinding> shadowed_bindings() {
  std::vector<vk::DescriptorBinding> b = scene_bindings(
      {.stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_RAYGEN_BIT_KHR | VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR,
       .vertex_buffers = true, .tlas = true});
  b.push_back({kBindingTriangle, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  b.push_back({kBindingColor, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  b.push_back({kBindingCounter, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_RAYGEN_BIT_KHR});
  return b;
}

vk::UniqueDescriptorSetLayout make_set_layout(const vk::Device& device) {
  const auto& caps = device.capabilities();
  if (!device.ray_tracing_enabled())
    throw vk::NoSuitableDevice(caps.name + " has no ray tracing enabled (shadows need VK_KHR_ray_tracing_pipeline and "
                               "VK_KHR_acceleration_structure)");
  if (!caps.geometry_shader)
    throw vk::NoSuitableDevice(caps.name + " cannot read gl_PrimitiveID in fragment shaders (no geometryShader feature)");
  return vk::create_descriptor_set_layout(device, shadowed_bindings());
}

vk::UniquePipelineLayout make_layout(const vk::Device& device, VkDescriptorSetLayout set) {
  return vk::create_pipeline_layout(device, std::span(&set, 1), {});
}

rt::RayTracingPipelineDesc shading_desc(VkPipelineLayout layout) {
  return surface_rt_pipeline({"surface/rt/forward_shade.rgen"}, layout);
}

}  // namespace

ShadowedForwardTargets create_shadowed_forward_targets(const vk::Device& device, VkExtent2D extent) {
  ShadowedForwardTargets t;
  t.extent = extent;
  t.color = vk::Image(device, extent, kColorFormat, VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.depth = vk::Image(device, extent, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.triangle = vk::Image(device, extent, kTriangleFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT);
  return t;
}

ShadowedForwardPass::ShadowedForwardPass(const vk::Device& device)
    : device_(device),
      set_layout_(make_set_layout(device)),
      layout_(make_layout(device, set_layout_.get())),
      shading_(device, shading_desc(layout_.get())) {
  if (!(device.format_properties(kColorFormat).optimalTilingFeatures & VK_FORMAT_FEATURE_STORAGE_IMAGE_BIT))
    throw vk::NoSuitableDevice(device.capabilities().name + " cannot store to R32G32B32A32_SFLOAT images");
  const std::vector<vk::DescriptorBinding> bindings = shadowed_bindings();
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), bindings);
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  counter_ = vk::Buffer(device, sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set_.set, kBindingCounter, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, counter_.get());

  vk::VertexPipelineDesc prepass;
  prepass.vertex_shader = "surface/depth.vert";
  prepass.fragment_shader = "surface/visibility.frag";
  prepass.layout = layout_.get();
  prepass.bindings = {{0, sizeof(float) * 3, VK_VERTEX_INPUT_RATE_VERTEX}};
  prepass.attributes = {{PRISMOID_SURFACE_VERTEX_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
  prepass.color_formats = {kTriangleFormat};
  prepass.depth_format = kDepthFormat;
  prepass.depth_compare = VK_COMPARE_OP_GREATER;  // reversed z, as ForwardPass's pre-pass
  prepass.depth_write = true;
  prepass_pipeline_ = vk::create_vertex_pipeline(device, prepass);
}

void ShadowedForwardPass::record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, const rt::SceneAccel& accel,
                                 ShadowedForwardTargets& targets, const Camera& camera, const ForwardSettings& settings,
                                 vk::GpuTimer& timer) {
  validate(camera);
  if (!(std::abs(settings.subpixel.x) <= 0.5 && std::abs(settings.subpixel.y) <= 0.5))
    throw std::invalid_argument("ShadowedForwardPass: the sub-pixel offset must lie within the pixel");
  // Every GPU coordinate is relative to one origin: the acceleration structure's must be the
  // shading buffers' (both the bounds centre of the same SurfaceScene).
  if (accel.origin() != scene.origin)
    throw std::invalid_argument("ShadowedForwardPass: the acceleration structure's origin differs from the surface scene's "
                                "(build both from the same SurfaceScene)");
  if (bound_scene_ != buffer_key(scene)) {
    write_scene_descriptors(device_, set_.set, scene, true);
    bound_scene_ = buffer_key(scene);
  }
  if (bound_tlas_ != accel.tlas_serial()) {
    rt::write_tlas_descriptor(device_, set_.set, PRISMOID_SURFACE_BINDING_TLAS, accel.tlas());
    bound_tlas_ = accel.tlas_serial();
  }
  if (bound_triangle_image_ != targets.triangle.serial() || bound_color_image_ != targets.color.serial()) {
    vk::write_storage_image_descriptor(device_, set_.set, kBindingTriangle, targets.triangle.view());
    vk::write_storage_image_descriptor(device_, set_.set, kBindingColor, targets.color.view());
    bound_triangle_image_ = targets.triangle.serial();
    bound_color_image_ = targets.color.serial();
  }
  const VkExtent2D e = targets.extent;
  const gpu::SurfaceFrame frame = surface_frame(scene, camera, e, settings.subpixel);
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));

  const VkViewport viewport{0.0f, 0.0f, float(e.width), float(e.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, e};
  const VkDeviceSize zero = 0;
  const VkBuffer positions = scene.positions.get();
  const uint32_t index_count = scene.triangle_count * 3;

  vkCmdFillBuffer(cmd, counter_.get(), 0, sizeof(uint32_t), 0u);
  vk::buffer_barrier(cmd, {counter_.get()}, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  {
    vk::ScopedPass pass(timer, cmd, "depth pre-pass");
    vk::image_barrier(cmd, targets.depth.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT);
    vk::image_barrier(cmd, targets.triangle.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_NONE,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = targets.depth.view();
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth.clearValue.depthStencil = {0.0f, 0};  // reversed z: 0 is infinitely far
    VkRenderingAttachmentInfo triangle{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    triangle.imageView = targets.triangle.view();
    triangle.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    triangle.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    triangle.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    triangle.clearValue.color.uint32[0] = 0u;  // no surface
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = scissor;
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &triangle;
    rendering.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &rendering);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    if (index_count > 0) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, prepass_pipeline_.get());
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set_.set, 0, nullptr);
      vkCmdBindVertexBuffers(cmd, 0, 1, &positions, &zero);
      vkCmdBindIndexBuffer(cmd, scene.indices.get(), 0, VK_INDEX_TYPE_UINT32);
      vkCmdDrawIndexed(cmd, index_count, 1, 0, 0, 0);
    }
    vkCmdEndRendering(cmd);
  }
  {
    vk::ScopedPass pass(timer, cmd, "forward shading");  // the name ForwardPass times its shading with
    vk::image_barrier(cmd, targets.triangle.get(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    vk::image_barrier(cmd, targets.color.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_NONE,
                      VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, shading_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, layout_.get(), 0, 1, &set_.set, 0, nullptr);
    shading_.trace(cmd, 0, e.width, e.height);
  }
  vk::image_barrier(cmd, targets.color.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                    VK_ACCESS_2_TRANSFER_READ_BIT);
  vk::buffer_barrier(cmd, {counter_.get()}, VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
}

uint64_t ShadowedForwardPass::read_shading_invocations() const {
  uint32_t value = 0;
  std::memcpy(&value, counter_.mapped(), sizeof(value));
  return value;
}

ForwardImage render_forward_shadowed(const vk::Device& device, ShadowedForwardPass& pass, const GpuSurfaceScene& scene,
                                     const rt::SceneAccel& accel, const Camera& camera, VkExtent2D extent,
                                     const ForwardSettings& settings) {
  if (extent.width == 0 || extent.height == 0) throw InputError(setting("size"), "the image size must be positive");
  ShadowedForwardTargets targets = create_shadowed_forward_targets(device, extent);
  vk::GpuTimer timer(device, 2);
  timer.submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, scene, accel, targets, camera, settings, timer); });
  ForwardImage image;
  image.width = extent.width;
  image.height = extent.height;
  image.rgba.resize(size_t(extent.width) * extent.height * 4);
  vk::read_image(device, targets.color, sizeof(float) * 4, std::as_writable_bytes(std::span(image.rgba)));
  if (settings.read_depth) image.depth = read_view_axis_depth(device, targets.depth, camera.near_distance);
  image.passes = timer.read();
  image.shading_invocations = pass.read_shading_invocations();
  image.shadows = true;
  return image;
}

ForwardImage render_forward_shadowed_supersampled(const vk::Device& device, ShadowedForwardPass& pass, const GpuSurfaceScene& scene,
                                                  const rt::SceneAccel& accel, const Camera& camera, VkExtent2D extent, uint32_t k) {
  return average_subpixel_frames(
      k, [&](const ForwardSettings& settings) { return render_forward_shadowed(device, pass, scene, accel, camera, extent, settings); });
}

}  // namespace prismoid::surface
