#pragma once
// The forward surface backend: ordinary per-pixel shading, the baseline for time and,
// supersampled, the visual reference of the shading-space backends. Two passes:
//  - "depth pre-pass": positions only, reversed-z depth (GREATER), no fragment shader;
//  - "forward shading": the same positions (invariant) tested EQUAL with early fragment tests,
//    so the shading code (shaders/surface/shading.glsl) runs exactly once per covered pixel,
//    then the sky where no surface is.
// Output: linear RGBA float (alpha 1 where a surface is seen, 0 on the sky). What it computes is
// reference::direct_light (renderer/reference/direct_light.hpp): direct light without shadows.
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec2.hpp>

#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/surface_image.hpp"
#include "renderer/surface/surface_frame.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

struct ForwardTargets {
  vk::Image color;        // RGBA32F linear radiance; alpha = coverage
  vk::Image depth;        // D32: near / distance along the view axis (0: nothing); readable (TRANSFER_SRC)
  vk::Image shade_count;  // R32UI: shading invocations per pixel (filled with count_shading)
  VkExtent2D extent{};
};
ForwardTargets create_forward_targets(const vk::Device& device, VkExtent2D extent);

struct ForwardSettings {
  // Where each pixel is sampled, in pixels from its centre (both in [-0.5, 0.5]).
  glm::dvec2 subpixel{0.0};
  // Count shading invocations per pixel into targets.shade_count (needs fragmentStoresAndAtomics).
  bool count_shading = false;
  // render_forward*: read the depth buffer back into ForwardImage::depth.
  bool read_depth = false;
};

class ForwardPass {
 public:
  // Throws vk::NoSuitableDevice when the device cannot read gl_PrimitiveID in fragment shaders
  // (geometryShader) or render to RGBA32F.
  explicit ForwardPass(const vk::Device& device);

  // Records both passes. Leaves targets.color (and with count_shading targets.shade_count) in
  // TRANSFER_SRC_OPTIMAL. One record per submission: the frame's uniforms live in one buffer
  // written now. `scene` and `targets` must outlive the submission.
  void record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, ForwardTargets& targets, const Camera& camera,
              const ForwardSettings& settings, vk::GpuTimer& timer);

  // Fragment-shader invocations of the last recorded shading draw of surfaces (pipeline
  // statistics; waits for the GPU). 0 where the device cannot count (counts_fragments() false).
  uint64_t read_fragment_invocations() const;
  bool counts_fragments() const { return statistics_.get() != VK_NULL_HANDLE; }

 private:
  void bind(const GpuSurfaceScene& scene, const ForwardTargets& targets);
  VkPipeline shading_pipeline(bool counted);

  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline depth_pipeline_;
  vk::UniquePipeline shading_pipeline_;
  vk::UniquePipeline counted_pipeline_;  // made on first use
  vk::UniquePipeline sky_pipeline_;
  vk::DescriptorSet set_;
  vk::Buffer frame_uniforms_;
  vk::UniqueQueryPool statistics_;
  SceneBufferKey bound_scene_{};  // what the descriptors name (serials: see vk::next_resource_serial)
  uint64_t bound_count_image_ = 0;
  bool counted_ = false;
};

// One frame rendered and read back: what the CLI and the tests use.
struct ForwardImage : SurfaceImage {
  std::vector<uint32_t> shade_counts;  // per pixel, with count_shading
  // With read_depth: per pixel the nearest surface's depth along the viewing axis, +inf where
  // none is (view_depth.hpp). Not averaged by the supersampled renders (their first frame's).
  std::vector<float> depth;
  std::vector<vk::PassTiming> passes;  // GPU time per pass (summed over the frames when supersampled)
  uint64_t fragment_invocations = 0;   // of the surfaces' shading draw (summed), when counted
  bool statistics = false;             // fragment_invocations was counted
  // The shadowed pass (shadowed_forward_pass.hpp): shade_surface_point calls, counted by the
  // ray-generation shader (one per covered pixel); fragment_invocations stays 0 there.
  uint64_t shading_invocations = 0;
  bool shadows = false;
};
ForwardImage render_forward(const vk::Device& device, ForwardPass& pass, const GpuSurfaceScene& scene, const Camera& camera,
                            VkExtent2D extent, const ForwardSettings& settings = {});
// The average of k x k frames sampled at sub-pixel offsets ((i + 0.5) / k - 0.5) in x and y:
// the supersampled visual reference. Coverage (alpha) is averaged too.
ForwardImage render_forward_supersampled(const vk::Device& device, ForwardPass& pass, const GpuSurfaceScene& scene,
                                         const Camera& camera, VkExtent2D extent, uint32_t k);
// The same average over any renderer of one frame at a sub-pixel offset (settings.subpixel).
ForwardImage average_subpixel_frames(uint32_t k, const std::function<ForwardImage(const ForwardSettings&)>& render);

}  // namespace prismoid::surface
