#pragma once
// ReSTIR GI hosted by the Htex backend (Li & Guo, "Real-time Seamless Object Space Shading",
// section 4): the GI passes of restir_gi.glsl run over the texels of HtexPass's task list (8 x 8
// per task shadel, launched indirectly like the shading pass) with the Htex hooks of
// shaders/surface/gi/htex_host.glsl:
//  - a sample's reservoir slot is its texel's physical pool slot, so a texel whose group keeps
//    its page keeps its reservoir across frames (temporal reuse without reprojection);
//  - history is valid when the slot's stamp names the same virtual texel and the previous frame
//    (a page newly allocated, reassigned, or a shadel not shaded last frame invalidates);
//  - spatial neighbours are walked over the surface at the sample's level (htex_walk.glsl, the
//    twin of htex_walk.cpp) and must be resident tasks this frame;
//  - the fallback ("persistent") layer holds a reservoir for every texel of one fixed level per
//    mesh, always allocated. Deviation: Li & Guo keep the finest level; a dense finest level
//    is too large in general (96 bytes per texel), so each mesh gets the finest level whose
//    texel count fits its share of a budget (persistent_texel_budget / meshes), at worst the
//    coarsest. A texel maps to the persistent texel containing it (its centre, from coarser).
// Passes: "gi samples" (per task texel: its point, triangle, weights, the direction to the eye),
// "gi initial+temporal" and "gi spatial" (which also stamps the slots). The output, f cos Lo W
// per texel, goes to HtexPass::indirect_radiance(), which the gather adds; the direct shading
// leaves the sky's ambient term out (HtexSettings::sky_ambient = false), the sky arriving
// through GI's bounce rays. Sum: emission + direct + one bounce (reference::radiance_leaving
// with max_bounces = 2, up to the area lights' shadow approximation and the sky reflected twice).
//
// Memory per pool texel: samples 48 B, two reservoirs 192 B, stamp 16 B (256 B, 16x the pool's
// own RGBA32F); plus 96 B per persistent texel.
#include <cstdint>
#include <vector>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/htex/htex_pass.hpp"
#include "renderer/surface/gi/restir_gi.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"

namespace prismoid::surface {

struct HtexGiOptions {
  uint64_t persistent_texel_budget = uint64_t(1) << 18;  // texels of the fallback layer over all meshes (96 B each)
};

class HtexGi {
 public:
  // `pass` must have been made with HtexSettings::indirect (the output buffer) and should use
  // sky_ambient = false. Keeps references to the device, pass, scene and acceleration structure
  // (same origin as the scene). Throws std::invalid_argument without the indirect buffer,
  // InputError when the reservoirs exceed the device's storage-buffer range, vk::NoSuitableDevice
  // without ray tracing.
  HtexGi(const vk::Device& device, const HtexPass& pass, const GpuSurfaceScene& scene, const rt::SceneAccel& accel,
         const HtexGiOptions& options = {});

  // Records the GI passes for frame `frame` (seeds; history needs consecutive frame numbers from
  // 0) between pass.record_shading and pass.record_gather of the same submission. One record per
  // submission, waited for before the next.
  void record(VkCommandBuffer cmd, const Camera& camera, VkExtent2D extent, uint32_t frame, const RestirGiSettings& settings,
              vk::GpuTimer* timer = nullptr);
  // Forgets every reservoir, stamp and the fallback layer (waits for the device).
  void reset();

  uint64_t reservoir_bytes() const;   // samples, slots, pass 1's reservoirs and the stamps (per pool texel)
  uint64_t persistent_bytes() const;  // the fallback layer
  const std::vector<uint32_t>& persistent_levels() const { return persistent_levels_; }  // per mesh
  uint64_t persistent_texels() const { return persistent_texels_; }
  const vk::Buffer& slots() const { return slots_; }
  const vk::Buffer& fallback() const { return fallback_; }

 private:
  const vk::Device& device_;
  const HtexPass& pass_;
  const GpuSurfaceScene& scene_;
  vk::UniqueDescriptorSetLayout gi_layout_, htex_layout_;
  vk::UniquePipelineLayout layout_;
  rt::RayTracingPipeline pipeline_;
  vk::DescriptorSet gi_set_, htex_set_;
  vk::Buffer frame_uniforms_;
  vk::Buffer samples_, slots_, temporal_, stamps_, fallback_, layers_, direct_;
  std::vector<uint32_t> persistent_levels_;
  uint64_t persistent_texels_ = 0;
};

// N frames of the Htex backend with GI, the camera fixed: each frame marking, allocation,
// shading, GI (frame numbers first_frame, first_frame + 1, ...), gather. The image is the mean of
// the frames (temporal accumulation; alpha: the last frame's coverage); with keep_frames each
// frame's RGBA too. Counters and pass timings are the last frame's.
struct HtexGiImage {
  HtexImage image;
  std::vector<std::vector<float>> frames;  // RGBA per frame (keep_frames)
};
HtexGiImage render_htex_gi(const vk::Device& device, HtexPass& pass, HtexGi& gi, const GpuSurfaceScene& scene,
                           VkAccelerationStructureKHR tlas, const Camera& camera, VkExtent2D extent, uint32_t frames,
                           const RestirGiSettings& settings, uint32_t first_frame = 0, bool keep_frames = false);

}  // namespace prismoid::surface
