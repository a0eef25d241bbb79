#pragma once
// ReSTIR GI in object space (Ouyang et al. 2021, "ReSTIR GI: Path Resampling for Real-Time Path
// Tracing"; in object space as Li & Guo, "Real-time Seamless Object Space Shading", section 4):
// one-bounce indirect light for a set of shading samples, with reservoirs that live in
// per-sample slots across frames (temporal reuse without reprojection), spatial reuse over
// neighbours on the surface and a persistent fallback layer for samples whose history is lost.
// Two ray-generation passes (no ray queries): "gi initial+temporal" and "gi spatial"; the
// shaders are shaders/surface/gi/ (restir_gi.glsl documents the estimator and the hooks a
// host provides). This class drives them over the dense sample set (gi_dense_set.hpp); a
// shading backend (Htex) supplies its own hooks and sample buffer the same way.
//
// Output per sample: the indirect radiance towards the sample's viewer (rgb), which the host
// adds to its direct shading of the sample (shade_surface_point with frame.sky_up.w = 1: the
// sky comes through GI). Their sum converges to reference::radiance_leaving with
// max_bounces = 2 (emission + direct + one bounce), up to the area lights' shadow
// approximation and the sky reflected twice (left out).
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/gi/gi_dense_set.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/vk/timer.hpp"
#include "shaders/shared/gi.h"

namespace prismoid::surface {

struct RestirGiSettings {
  bool unbiased = false;            // visibility-checked reuse and the count normalization (else as the paper ships)
  bool temporal = true;             // merge the slot's history (last frame's final reservoir)
  bool fallback = true;             // merge the fallback layer's reservoir where the history is invalid
  bool new_candidates = true;       // trace a fresh bounce per sample (false: reuse only, for tests)
  bool write_direct = false;        // also write each sample's direct shading (read_direct)
  uint32_t spatial_neighbours = 4;  // k candidates per sample (at most 16; 0: no spatial reuse)
  double radius = 2.0;              // neighbourhood radius, in the sample set's units (dense set: texels)
  double m_cap = 20.0;              // the history's M is capped to this
  double max_normal_angle_degrees = 25.0;  // neighbours whose surfaces turn further are not used
  double jacobian_limit = 3.0;      // tau: reconnection shifts with a Jacobian outside [1/tau, tau] are not made
};

// The GI passes' descriptor set 0 (shaders/shared/gi.h), whatever the host: the scene with its
// vertex buffers and TLAS, the GI buffers and two host buffers. Throws vk::NoSuitableDevice
// without ray tracing.
vk::UniqueDescriptorSetLayout gi_set_layout(const vk::Device& device);
std::vector<vk::DescriptorBinding> gi_bindings();

// The GI passes' layout and ray-tracing pipeline over the dense sample set: independent of the
// scene, so one serves every RestirGi of a device (compiling it is the slow part on lavapipe).
class RestirGiPipeline {
 public:
  // Throws vk::NoSuitableDevice without ray tracing.
  explicit RestirGiPipeline(const vk::Device& device);
  VkDescriptorSetLayout set_layout() const { return set_layout_.get(); }
  VkPipelineLayout layout() const { return layout_.get(); }
  const rt::RayTracingPipeline& pipeline() const { return pipeline_; }

 private:
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  rt::RayTracingPipeline pipeline_;
};

class RestirGi {
 public:
  // Keeps references to the device, scene and acceleration structure (same origin as the
  // scene: both default to the bounds' centre), which must outlive it; uploads the samples and
  // the neighbour table. Throws vk::NoSuitableDevice without ray tracing, InputError for an
  // empty sample set.
  RestirGi(const vk::Device& device, const GpuSurfaceScene& scene, const rt::SceneAccel& accel, const GiDenseSet& set);
  // The same with a shared pipeline (which must outlive it).
  RestirGi(const vk::Device& device, const RestirGiPipeline& pipeline, const GpuSurfaceScene& scene, const rt::SceneAccel& accel,
           const GiDenseSet& set);

  uint32_t sample_count() const { return count_; }

  // Records both passes for frame `frame_index` (seeds the random streams), bracketed by the
  // timer's passes "gi initial+temporal" and "gi spatial" when a timer is given. One record per
  // submission, waited for before the next (the history flags are written now).
  void record(VkCommandBuffer cmd, uint32_t frame_index, const RestirGiSettings& settings, vk::GpuTimer* timer = nullptr);

  // Marks samples whose slot lost its history (a disocclusion, a fresh allocation): their next
  // frame reads no history (the fallback layer instead, when enabled). Every slot is invalid
  // before the first frame and valid after each frame unless marked.
  void invalidate_history(std::span<const uint32_t> samples);
  // Forgets everything: reservoirs, fallback layer and history.
  void reset();

  // After the recorded frame completed (each waits for the device):
  std::vector<glm::vec3> read_indirect() const;  // per sample, rgb
  std::vector<glm::vec3> read_direct() const;    // per sample, rgb (frames with write_direct)
  std::vector<gpu::GiReservoir> read_reservoirs() const;  // the slots (final reservoirs)
  std::vector<gpu::GiReservoir> read_temporal() const;    // pass 1's output
  std::vector<gpu::GiReservoir> read_fallback() const;

 private:
  RestirGi(const vk::Device& device, std::unique_ptr<RestirGiPipeline> owned, const RestirGiPipeline* shared,
           const GpuSurfaceScene& scene, const rt::SceneAccel& accel, const GiDenseSet& set);
  std::vector<std::byte> read(const vk::Buffer& buffer) const;

  const vk::Device& device_;
  std::unique_ptr<RestirGiPipeline> own_pipeline_;  // when none was shared
  const RestirGiPipeline& pipeline_;
  uint32_t count_ = 0;
  vk::DescriptorSet set_;
  vk::Buffer frame_uniforms_;
  vk::Buffer samples_, slots_, temporal_, fallback_, output_, direct_;
  vk::Buffer history_, neighbours_;
  std::vector<uint32_t> history_valid_;
  bool clear_ = true;  // the next record starts by clearing the reservoirs
};

}  // namespace prismoid::surface
