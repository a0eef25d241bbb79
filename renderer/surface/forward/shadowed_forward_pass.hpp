#pragma once
// The forward surface backend with shadows, for devices with ray-tracing pipelines (fragment
// shaders cannot trace: no ray queries). Two passes:
//  - "depth pre-pass": the raster pre-pass of ForwardPass (reversed-z depth, GREATER) that also
//    writes each pixel's nearest triangle as global index + 1 into an R32UI target
//    (shaders/surface/visibility.frag; 0 where no surface is);
//  - "forward shading" (the name ForwardPass uses): one ray-generation invocation per pixel (surface/rt/forward_shade.rgen)
//    rebuilds the point where the pixel's sample ray (ForwardSettings::subpixel, as the raster)
//    meets that triangle's plane, shades it with the shared code and the shadow rays of
//    shaders/surface/shadow_rays.glsl through the scene's TLAS, and writes the sky elsewhere.
// Output as ForwardPass (linear RGBA float, alpha = coverage). What it computes is
// reference::direct_light with DirectLightOptions::shadows (renderer/reference/direct_light.hpp).
// The shading invocations (one per covered pixel) are counted by the shader itself.
#include <cstdint>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/forward/forward_pass.hpp"

namespace prismoid::surface {

struct ShadowedForwardTargets {
  vk::Image color;     // RGBA32F, written by the ray-generation shader
  vk::Image depth;     // D32 reversed z; readable (TRANSFER_SRC)
  vk::Image triangle;  // R32UI: global triangle + 1 (0: none)
  VkExtent2D extent{};
};
ShadowedForwardTargets create_shadowed_forward_targets(const vk::Device& device, VkExtent2D extent);

class ShadowedForwardPass {
 public:
  // Throws vk::NoSuitableDevice when the device has no ray tracing enabled or cannot read
  // gl_PrimitiveID in fragment shaders.
  explicit ShadowedForwardPass(const vk::Device& device);

  // Records both passes; leaves targets.color in TRANSFER_SRC_OPTIMAL. `accel` must be built
  // from the same SurfaceScene as `scene`, with the same origin (std::invalid_argument if not).
  // ForwardSettings::count_shading is ignored: the invocations are always counted.
  void record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, const rt::SceneAccel& accel, ShadowedForwardTargets& targets,
              const Camera& camera, const ForwardSettings& settings, vk::GpuTimer& timer);

  // shade_surface_point calls of the last recorded frame (waits for nothing: read after the
  // submission completed).
  uint64_t read_shading_invocations() const;

 private:
  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline prepass_pipeline_;
  rt::RayTracingPipeline shading_;
  vk::DescriptorSet set_;
  vk::Buffer frame_uniforms_;
  vk::Buffer counter_;
  SceneBufferKey bound_scene_{};  // what the descriptors name (serials: see vk::next_resource_serial)
  uint64_t bound_tlas_ = 0, bound_triangle_image_ = 0, bound_color_image_ = 0;
};

ForwardImage render_forward_shadowed(const vk::Device& device, ShadowedForwardPass& pass, const GpuSurfaceScene& scene,
                                     const rt::SceneAccel& accel, const Camera& camera, VkExtent2D extent,
                                     const ForwardSettings& settings = {});
// The k x k sub-pixel average, as render_forward_supersampled.
ForwardImage render_forward_shadowed_supersampled(const vk::Device& device, ShadowedForwardPass& pass, const GpuSurfaceScene& scene,
                                                  const rt::SceneAccel& accel, const Camera& camera, VkExtent2D extent, uint32_t k);

}  // namespace prismoid::surface
