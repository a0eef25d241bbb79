#pragma once
// Recording steps the texture-space backends (Htex, texel shading) share: the depth pre-pass
// followed by an EQUAL-tested draw whose fragment shader runs once per visible pixel (marking
// or queueing), the full-screen gather into the colour target, and reading a device buffer
// back. Each backend keeps its own pipelines, descriptor set and push constants.
#include <cstddef>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include <vulkan/vulkan.h>

#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/surface_image.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/handle.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"

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

// Binds a graphics pipeline with the binding's set and push constants.
void bind_graphics(VkCommandBuffer cmd, VkPipeline pipeline, const PassBinding& binding);
// The whole of `extent` as the dynamic viewport and scissor.
void set_viewport(VkCommandBuffer cmd, VkExtent2D extent);

// Empty when the device can run a texture-space backend (gl_PrimitiveID and storage writes in
// fragment shaders, a ray-generation shading pass launched indirectly, RGBA32F targets), else
// why not; `backend` names it in the message.
std::string texture_space_device_problem(const vk::Device& device, const std::string& backend);

// What a texture-space backend draws into: linear RGBA32F radiance (alpha = coverage), a D32
// depth (reversed z) and a visibility buffer (uvec4 per pixel: triangle + 1, 0 for the sky, a
// backend value such as a level, then two barycentric weights as float bits).
struct TextureSpaceTargets {
  vk::Image color;
  vk::Image depth;
  vk::Buffer visibility;
  VkExtent2D extent{};
};
TextureSpaceTargets create_texture_space_targets(const vk::Device& device, VkExtent2D extent);

// One frame read back: what the CLI and the tests use (each backend adds its counters).
struct TextureSpaceImage : SurfaceImage {
  std::vector<glm::uvec4> visibility;  // per pixel, as TextureSpaceTargets::visibility
  std::vector<vk::PassTiming> passes;
};
// Reads the colour, the visibility buffer and the timer after a submission completed.
void read_texture_space_image(const vk::Device& device, const TextureSpaceTargets& targets, vk::GpuTimer& timer, TextureSpaceImage& image);

// Writes the scene's descriptors, the TLAS and the visibility buffer into a backend's set, each
// only when it changed since the last call.
class SceneSetBinding {
 public:
  void update(const vk::Device& device, VkDescriptorSet set, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
              const vk::Buffer& visibility, uint32_t visibility_binding);

 private:
  // What the descriptors name: the scene's and the visibility buffer's serials
  // (vk::next_resource_serial), and the TLAS, written again with every new scene too (its
  // handle alone could be a destroyed one's).
  SceneBufferKey scene_{};
  VkAccelerationStructureKHR tlas_ = VK_NULL_HANDLE;
  uint64_t visibility_ = 0;
};

// The shading pass ("shading" in the timer): after the pass that wrote the task list and the
// launch size (fragment or compute), raygen `raygen` of `pipeline` launched indirectly from
// `launch`; then a barrier for the gather's reads.
void record_indirect_shading(VkCommandBuffer cmd, vk::GpuTimer& timer, const rt::RayTracingPipeline& pipeline, uint32_t raygen,
                             const PassBinding& binding, VkDeviceAddress launch);

// One frame of a backend rendered and read back (Image: the backend's TextureSpaceImage with
// its counters; Pass: record(cmd, scene, tlas, targets, camera, timer) and read_counters()).
template <typename Image, typename Pass>
Image render_texture_space_frame(const vk::Device& device, Pass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                                 const Camera& camera, VkExtent2D extent) {
  TextureSpaceTargets targets = create_texture_space_targets(device, extent);
  vk::GpuTimer timer(device, 8);
  timer.submit_and_wait([&](VkCommandBuffer cmd) { pass.record(cmd, scene, tlas, targets, camera, timer); });
  Image image;
  read_texture_space_image(device, targets, timer, image);
  image.counters = pass.read_counters();
  return image;
}

// Copies a backend's state buffer to its host-visible read-back buffer at the end of a frame.
void record_state_readback(VkCommandBuffer cmd, const vk::Buffer& state, const vk::Buffer& readback, VkDeviceSize bytes);
// The state record_state_readback left in `readback` (host-visible), after the frame's fence.
template <typename State>
State read_mapped(const vk::Buffer& readback) {
  State s{};
  std::memcpy(&s, readback.mapped(), sizeof(s));
  return s;
}

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
