#include "renderer/surface/forward/forward_pass.hpp"

#include "renderer/surface/view_depth.hpp"
#include "renderer/surface/scene_descriptors.hpp"
#include "renderer/surface/surface_frame.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

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
constexpr VkFormat kCountFormat = VK_FORMAT_R32_UINT;

// The scene's bindings (no vertex buffers: the rasterizer interpolates the attributes) and the
// shading counter.
std::vector<vk::DescriptorBinding> forward_bindings() {
  std::vector<vk::DescriptorBinding> b =
      scene_bindings({.stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, .vertex_buffers = false, .tlas = false});
  b.push_back({PRISMOID_SURFACE_BINDING_SHADE_COUNT, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_FRAGMENT_BIT});
  return b;
}

std::vector<VkVertexInputBindingDescription> vertex_bindings(bool attributes) {
  std::vector<VkVertexInputBindingDescription> b{{0, sizeof(float) * 3, VK_VERTEX_INPUT_RATE_VERTEX}};
  if (attributes) b.push_back({1, sizeof(float) * 6, VK_VERTEX_INPUT_RATE_VERTEX});
  return b;
}

std::vector<VkVertexInputAttributeDescription> vertex_attributes(bool attributes) {
  std::vector<VkVertexInputAttributeDescription> a{{PRISMOID_SURFACE_VERTEX_POSITION, 0, VK_FORMAT_R32G32B32_SFLOAT, 0}};
  if (attributes) {
    a.push_back({PRISMOID_SURFACE_VERTEX_NORMAL, 1, VK_FORMAT_R32G32B32_SFLOAT, 0});
    a.push_back({PRISMOID_SURFACE_VERTEX_COLOR, 1, VK_FORMAT_R32G32B32_SFLOAT, sizeof(float) * 3});
  }
  return a;
}

}  // namespace

ForwardTargets create_forward_targets(const vk::Device& device, VkExtent2D extent) {
  ForwardTargets t;
  t.extent = extent;
  t.color = vk::Image(device, extent, kColorFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.depth = vk::Image(device, extent, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  t.shade_count = vk::Image(device, extent, kCountFormat,
                            VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
  return t;
}

ForwardPass::ForwardPass(const vk::Device& device) : device_(device) {
  const auto& caps = device.capabilities();
  if (!caps.geometry_shader)
    throw vk::NoSuitableDevice(caps.name + " cannot read gl_PrimitiveID in fragment shaders (no geometryShader feature)");
  if (!(device.format_properties(kColorFormat).optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT))
    throw vk::NoSuitableDevice(caps.name + " cannot render to R32G32B32A32_SFLOAT images");
  const std::vector<vk::DescriptorBinding> bindings = forward_bindings();
  set_layout_ = vk::create_descriptor_set_layout(device, bindings);
  VkDescriptorSetLayout sets[] = {set_layout_.get()};
  layout_ = vk::create_pipeline_layout(device, sets, {});
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), bindings);
  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::SurfaceFrame), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set_.set, PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());

  vk::VertexPipelineDesc depth;
  depth.vertex_shader = "surface/depth.vert";
  depth.layout = layout_.get();
  depth.bindings = vertex_bindings(false);
  depth.attributes = vertex_attributes(false);
  depth.depth_format = kDepthFormat;
  depth.depth_compare = VK_COMPARE_OP_GREATER;  // reversed z: near / distance, greater is nearer
  depth.depth_write = true;
  depth_pipeline_ = vk::create_vertex_pipeline(device, depth);

  sky_pipeline_ = [&] {
    vk::VertexPipelineDesc sky;
    sky.vertex_shader = "surface/sky.vert";
    sky.fragment_shader = "surface/sky.frag";
    sky.layout = layout_.get();
    sky.color_formats = {kColorFormat};
    sky.depth_format = kDepthFormat;
    sky.depth_compare = VK_COMPARE_OP_EQUAL;  // where the depth is still the cleared 0
    return vk::create_vertex_pipeline(device, sky);
  }();
  shading_pipeline(false);

  if (caps.pipeline_statistics) {
    VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    info.queryCount = 1;
    info.pipelineStatistics = VK_QUERY_PIPELINE_STATISTIC_FRAGMENT_SHADER_INVOCATIONS_BIT;
    VkQueryPool pool;
    vk::check(vkCreateQueryPool(device.get(), &info, nullptr, &pool), "vkCreateQueryPool (pipeline statistics)");
    statistics_ = vk::UniqueQueryPool(device.get(), pool);
  }
}

VkPipeline ForwardPass::shading_pipeline(bool counted) {
  vk::UniquePipeline& slot = counted ? counted_pipeline_ : shading_pipeline_;
  if (slot) return slot.get();
  if (counted && !device_.capabilities().fragment_stores)
    throw vk::NoSuitableDevice(device_.capabilities().name + " cannot write storage images from fragment shaders");
  vk::VertexPipelineDesc desc;
  desc.vertex_shader = "surface/forward.vert";
  desc.fragment_shader = counted ? "surface/forward_counted.frag" : "surface/forward.frag";
  desc.layout = layout_.get();
  desc.bindings = vertex_bindings(true);
  desc.attributes = vertex_attributes(true);
  desc.color_formats = {kColorFormat};
  desc.depth_format = kDepthFormat;
  desc.depth_compare = VK_COMPARE_OP_EQUAL;  // only the surface the pre-pass kept
  slot = vk::create_vertex_pipeline(device_, desc);
  return slot.get();
}

void ForwardPass::bind(const GpuSurfaceScene& scene, const ForwardTargets& targets) {
  if (bound_scene_ != buffer_key(scene)) {
    write_scene_descriptors(device_, set_.set, scene, false);
    bound_scene_ = buffer_key(scene);
  }
  if (bound_count_image_ != targets.shade_count.serial()) {
    vk::write_storage_image_descriptor(device_, set_.set, PRISMOID_SURFACE_BINDING_SHADE_COUNT, targets.shade_count.view());
    bound_count_image_ = targets.shade_count.serial();
  }
}

void ForwardPass::record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, ForwardTargets& targets, const Camera& camera,
                         const ForwardSettings& settings, vk::GpuTimer& timer) {
  validate(camera);
  if (!(std::abs(settings.subpixel.x) <= 0.5 && std::abs(settings.subpixel.y) <= 0.5))
    throw std::invalid_argument("ForwardPass: the sub-pixel offset must lie within the pixel");
  const VkPipeline shading = shading_pipeline(settings.count_shading);  // before any recording state
  bind(scene, targets);
  const VkExtent2D e = targets.extent;
  const gpu::SurfaceFrame frame = surface_frame(scene, camera, e, settings.subpixel);
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));

  const VkViewport viewport{0.0f, 0.0f, float(e.width), float(e.height), 0.0f, 1.0f};
  const VkRect2D scissor{{0, 0}, e};
  const VkDeviceSize zero = 0;
  const VkBuffer vertex_buffers[] = {scene.positions.get(), scene.attributes.get()};
  const VkDeviceSize offsets[] = {0, 0};
  const uint32_t index_count = scene.triangle_count * 3;

  VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
  depth.imageView = targets.depth.view();
  depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
  VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
  rendering.renderArea = scissor;
  rendering.layerCount = 1;
  rendering.pDepthAttachment = &depth;

  {
    vk::ScopedPass pass(timer, cmd, "depth pre-pass");
    vk::image_barrier(cmd, targets.depth.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT);
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    depth.clearValue.depthStencil = {0.0f, 0};  // reversed z: 0 is infinitely far
    vkCmdBeginRendering(cmd, &rendering);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    if (index_count > 0) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, depth_pipeline_.get());
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set_.set, 0, nullptr);
      vkCmdBindVertexBuffers(cmd, 0, 1, vertex_buffers, &zero);
      vkCmdBindIndexBuffer(cmd, scene.indices.get(), 0, VK_INDEX_TYPE_UINT32);
      vkCmdDrawIndexed(cmd, index_count, 1, 0, 0, 0);
    }
    vkCmdEndRendering(cmd);
  }

  if (settings.count_shading) {
    vk::image_barrier(cmd, targets.shade_count.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkClearColorValue clear{};
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, targets.shade_count.get(), VK_IMAGE_LAYOUT_GENERAL, &clear, 1, &range);
    vk::image_barrier(cmd, targets.shade_count.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  }
  const bool count_fragments = statistics_.get() != VK_NULL_HANDLE;
  if (count_fragments) vkCmdResetQueryPool(cmd, statistics_.get(), 0, 1);
  {
    vk::ScopedPass pass(timer, cmd, "forward shading");
    vk::image_barrier(cmd, targets.color.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                      VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    vk::image_barrier(cmd, targets.depth.get(), VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT,
                      VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT, VK_IMAGE_ASPECT_DEPTH_BIT);
    VkRenderingAttachmentInfo color{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    color.imageView = targets.color.view();
    color.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.clearValue.color = {{0.0f, 0.0f, 0.0f, 0.0f}};
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_NONE;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &color;
    vkCmdBeginRendering(cmd, &rendering);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set_.set, 0, nullptr);
    if (count_fragments) vkCmdBeginQuery(cmd, statistics_.get(), 0, 0);
    if (index_count > 0) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, shading);
      vkCmdBindVertexBuffers(cmd, 0, 2, vertex_buffers, offsets);
      vkCmdBindIndexBuffer(cmd, scene.indices.get(), 0, VK_INDEX_TYPE_UINT32);
      vkCmdDrawIndexed(cmd, index_count, 1, 0, 0, 0);
    }
    if (count_fragments) vkCmdEndQuery(cmd, statistics_.get(), 0);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, sky_pipeline_.get());
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdEndRendering(cmd);
  }
  counted_ = count_fragments;
  vk::image_barrier(cmd, targets.color.get(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                    VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  if (settings.count_shading)
    vk::image_barrier(cmd, targets.shade_count.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                      VK_ACCESS_2_TRANSFER_READ_BIT);
}

uint64_t ForwardPass::read_fragment_invocations() const {
  if (statistics_.get() == VK_NULL_HANDLE || !counted_) return 0;
  uint64_t value = 0;
  vk::check(vkGetQueryPoolResults(device_.get(), statistics_.get(), 0, 1, sizeof(value), &value, sizeof(value),
                                  VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
            "vkGetQueryPoolResults (pipeline statistics)");
  return value;
}

ForwardImage render_forward(const vk::Device& device, ForwardPass& pass, const GpuSurfaceScene& scene, const Camera& camera,
                            VkExtent2D extent, const ForwardSettings& settings) {
  if (extent.width == 0 || extent.height == 0) throw InputError(setting("size"), "the image size must be positive");
  ForwardTargets targets = create_forward_targets(device, extent);
  vk::GpuTimer timer(device, 2);
  timer.submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, scene, targets, camera, settings, timer); });
  ForwardImage image;
  image.width = extent.width;
  image.height = extent.height;
  const size_t pixels = size_t(extent.width) * extent.height;
  image.rgba.resize(pixels * 4);
  vk::read_image(device, targets.color, sizeof(float) * 4, std::as_writable_bytes(std::span(image.rgba)));
  if (settings.read_depth) image.depth = read_view_axis_depth(device, targets.depth, camera.near_distance);
  if (settings.count_shading) {
    image.shade_counts.resize(pixels);
    vk::read_image(device, targets.shade_count, sizeof(uint32_t), std::as_writable_bytes(std::span(image.shade_counts)));
  }
  image.passes = timer.read();
  image.statistics = pass.counts_fragments();
  image.fragment_invocations = pass.read_fragment_invocations();
  return image;
}

ForwardImage render_forward_supersampled(const vk::Device& device, ForwardPass& pass, const GpuSurfaceScene& scene,
                                         const Camera& camera, VkExtent2D extent, uint32_t k) {
  return average_subpixel_frames(k, [&](const ForwardSettings& settings) { return render_forward(device, pass, scene, camera, extent, settings); });
}

ForwardImage average_subpixel_frames(uint32_t k, const std::function<ForwardImage(const ForwardSettings&)>& render) {
  if (k == 0 || k > 64) throw InputError(setting("supersample"), "must be between 1 and 64 samples per pixel side");
  ForwardImage sum;
  std::vector<double> accumulated;
  for (uint32_t j = 0; j < k; ++j)
    for (uint32_t i = 0; i < k; ++i) {
      ForwardSettings settings;
      settings.subpixel = {(i + 0.5) / k - 0.5, (j + 0.5) / k - 0.5};
      const ForwardImage frame = render(settings);
      if (accumulated.empty()) {
        sum = frame;
        accumulated.assign(frame.rgba.begin(), frame.rgba.end());
        continue;
      }
      for (size_t p = 0; p < accumulated.size(); ++p) accumulated[p] += double(frame.rgba[p]);
      for (size_t p = 0; p < sum.passes.size() && p < frame.passes.size(); ++p) sum.passes[p].gpu_ms += frame.passes[p].gpu_ms;
      sum.fragment_invocations += frame.fragment_invocations;
      sum.shading_invocations += frame.shading_invocations;
    }
  const double scale = 1.0 / (double(k) * double(k));
  for (size_t p = 0; p < accumulated.size(); ++p) sum.rgba[p] = static_cast<float>(accumulated[p] * scale);
  return sum;
}

}  // namespace prismoid::surface
