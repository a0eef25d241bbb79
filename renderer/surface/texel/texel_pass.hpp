#pragma once
// The texel shading backend (Hillesland & Yang 2016, "Texel Shading") over the
// static atlas of texel_atlas.hpp. Per frame:
//  - "pre-z + queue": a depth pre-pass, then an EQUAL-tested pass whose fragment shader runs
//    once per visible pixel (shaders/surface/texel/queue.frag): the pixel's barycentric weights
//    on its triangle's plane, its level from the atlas-coordinate change one pixel right and down
//    (plus the mip bias), its four bilinear taps; each tap's 8 x 8 tile whose cache stamp is
//    older than the age threshold is claimed and queued (the paper's Algorithm 1 with its cache
//    texture of frame numbers). (triangle + 1, level, weights) go to a visibility buffer.
//  - "shading": ONE ray-generation shader (shade.rgen; shade_unshadowed.rgen without shadows),
//    8 x 8 invocations per queued tile through vkCmdTraceRaysIndirectKHR: texel -> triangle
//    index texture -> barycentric weights of its centre -> the shared shading code -> the result
//    texture (a storage buffer holding every level).
//  - "gather": a full-screen pass: per pixel the same taps, blended by hand from the result.
//
// Shading rate control: `lod_bias` (the paper's mip bias: +1 shades a quarter of the texels)
// and `max_age` (reuse shading up to that many frames old: 1 shades every needed tile every
// frame). Reusing across frames is only right while nothing the shading depends on changed; the
// caller decides and calls invalidate_shading() otherwise (as for Htex, plan_shading_reuse).
//
// Deviations from the paper: the result and index textures are storage buffers holding all
// levels one after the other (as the paper's D3D11 layout puts levels side by side in one
// texture); shading is a ray-generation shader (shadow rays without ray queries); bilinear
// filtering is by hand in float (exact against the CPU twin) and at one level (no trilinear).
#include <cstdint>
#include <string>
#include <vector>

#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/texel/texel_atlas.hpp"
#include "renderer/surface/texture_space_passes.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"

namespace prismoid::surface {

struct TexelSettings {
  bool shadows = true;
  float lod_bias = 0.0f;  // added to log2 of the footprint before rounding down
  uint32_t max_age = 1;   // frames a tile's shading may be reused (1: shade every needed tile every frame)
};

// Empty when the device can run the texel backend, else why not (what TexelPass would throw).
std::string texel_device_problem(const vk::Device& device);

// The atlas for `scene` under `settings`; when the density is left to the target texel count
// (texels_per_unit == 0), the target is halved until the result texture fits the device's
// storage-buffer range (lavapipe's is 128 MiB).
texel::TexelAtlas build_texel_atlas_for(const vk::Device& device, const SurfaceScene& scene, texel::AtlasSettings settings = {});

// Visibility per pixel: triangle + 1 (0: sky), level, b1 and b2 as float bits.
using TexelTargets = TextureSpaceTargets;
inline TexelTargets create_texel_targets(const vk::Device& device, VkExtent2D extent) { return create_texture_space_targets(device, extent); }

struct TexelCounters {
  uint32_t queued_tiles = 0;   // tiles shaded this frame
  uint32_t shaded_texels = 0;  // their texels that hold a triangle
  uint32_t hole_pixels = 0;    // gathered pixels with a tap never shaded (0 unless something is wrong)
  uint64_t atlas_bytes = 0;    // result, triangle index and cache
};

class TexelPass {
 public:
  // `atlas` must outlive the pass. Throws vk::NoSuitableDevice (texel_device_problem) and
  // InputError when the atlas exceeds the device's storage-buffer range.
  TexelPass(const vk::Device& device, const texel::TexelAtlas& atlas, const TexelSettings& settings = {});

  // Records the three passes; leaves targets.color in TRANSFER_SRC_OPTIMAL. One record per
  // submission. The TLAS must be built relative to scene.origin.
  void record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, TexelTargets& targets,
              const Camera& camera, vk::GpuTimer& timer);

  TexelCounters read_counters() const;
  // The next frame shades every needed tile (the cache forgets every stamp).
  void invalidate_shading() { invalidate_ = true; }
  const TexelSettings& settings() const { return settings_; }
  void set_settings(const TexelSettings& settings);
  const texel::TexelAtlas& atlas() const { return atlas_; }
  const vk::Buffer& result() const { return result_; }
  const vk::Buffer& tasks() const { return tasks_; }
  const vk::Buffer& cache() const { return cache_; }
  std::vector<std::byte> read_buffer(const vk::Buffer& buffer) const;

 private:
  void bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const TexelTargets& targets);

  const vk::Device& device_;
  const texel::TexelAtlas& atlas_;
  TexelSettings settings_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline depth_pipeline_, queue_pipeline_, gather_pipeline_;
  rt::RayTracingPipeline shade_pipeline_;
  vk::DescriptorSet set_;
  vk::Buffer frame_uniforms_, triangles_, triangle_index_, cache_, tasks_, result_, state_, readback_;
  uint32_t frame_stamp_ = 0;
  bool invalidate_ = false;
  SceneSetBinding bound_;
};

// One frame rendered and read back: what the CLI and the tests use.
struct TexelImage : TextureSpaceImage {
  TexelCounters counters;
};
TexelImage render_texel(const vk::Device& device, TexelPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                        const Camera& camera, VkExtent2D extent);

}  // namespace prismoid::surface
