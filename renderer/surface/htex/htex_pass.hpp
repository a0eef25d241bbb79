#pragma once
// The Htex object-space shading backend (Li & Guo, "Real-time Seamless Object Space Shading",
// section 3; Htex: Barbier & Dupuy 2022). Shading lives on per-edge texture quads packed in
// one virtual atlas (htex_layout.hpp, htex_tables.hpp); per frame:
//  - "pre-z + marking": a depth pre-pass, then an EQUAL-tested pass whose fragment shader runs
//    once per visible pixel (shaders/surface/htex/mark.frag): barycentric weights of the pixel's
//    ray on its triangle's plane, the level of detail from the weights one pixel right and down
//    (reference::htex_level_of_detail's formula), rounded to the nearest level; every virtual
//    shadel the lookup's footprint at that level reads is marked in the occupancy bits of its
//    shadel group; (triangle + 1, level, weights) go to a visibility buffer.
//  - "allocation" (compute, allocate.comp): while the marked groups exceed the pool, a bias pass
//    raises every pixel's level to at least 1, 2, ... and re-marks (Li & Guo 3.3 bias the
//    level-0 groups; raising all pixels below the bias level repeats that step), up to the
//    coarsest level; then groups no longer marked release their pages to a free list and newly
//    marked groups take one. A group that stays marked keeps its page: what is stored per texel
//    (the shading, and with GI the texel's reservoir: htex_gi.hpp) persists across frames at
//    the same slot.
//    When the pool is still too small, the groups left without a page are counted (overflow);
//    nothing is written outside the pool and the gather renormalizes over the resident texels.
//    The task list (every marked shadel of a resident group) and the indirect launch size are
//    written on the GPU.
//  - "shading": ONE ray-generation shader (shade.rgen; shade_unshadowed.rgen without shadows),
//    8 x 8 invocations per task shadel through vkCmdTraceRaysIndirectKHR: per texel its point
//    (vertex-corner texels at the vertex, ghost texels in the face's plane) -> triangle and
//    barycentrics -> shading_input_at -> shade_surface_point (with shadow_rays.glsl) -> the
//    texel's RGBA32F pool slot.
//  - "gather": a full-screen pass: per pixel, footprint -> page table -> pool, normalized blend;
//    the sky where nothing was seen. RGBA32F out, alpha = coverage, like the forward backend.
//
// Hook for indirect light (ReSTIR GI): with HtexSettings::indirect the pass owns a second
// buffer, indirect_radiance(), one vec4 per pool slot, which the gather adds to the pool's
// value. A GI pass records between record_shading() and record_gather(), walks the task list
// (tasks(), launch size at state() offset 0) and writes indirect radiance per texel slot.
//
// Deviations from the paper: shading is a ray-generation shader (shadow rays need a pipeline:
// no ray queries on the GPU machine); allocation is a free-list stack of pages, one page per
// shadel group, not a binned chunk allocator; the bias is per frame and global (every pixel
// below the bias level), not per group.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/htex/htex_tables.hpp"
#include "renderer/surface/texture_space_passes.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"

namespace prismoid::surface {

struct HtexSettings {
  uint32_t pool_pages = 1024;      // physical pages of 4096 texels (64 KiB of RGBA32F each)
  bool shadows = true;             // shadow rays from every texel (false: every light visible)
  bool indirect = false;           // allocate indirect_radiance() and add it at gather (GI hook)
  float lod_bias = 0.0f;           // added to the level of detail before rounding
  bool snap_vertex_corners = true; // false only in tests: the control that shows seams
  // Shadels shaded in an earlier frame whose group kept its page are not shaded again. Only
  // right while nothing their shading depends on changed (lights, materials, shadows setting;
  // and the camera where shading is view-dependent): the caller decides (plan_shading_reuse)
  // and calls invalidate_shading() when it no longer holds.
  bool reuse_shading = false;
  bool sky_ambient = true;         // false with GI (HtexGi): frame.sky_up.w = 1, the sky arrives through GI's rays
};

// Empty when the device can run the Htex backend, else why not (what HtexPass would throw).
std::string htex_device_problem(const vk::Device& device);

// Visibility per pixel: triangle + 1 (0: sky), level, b1 and b2 as float bits.
using HtexTargets = TextureSpaceTargets;
inline HtexTargets create_htex_targets(const vk::Device& device, VkExtent2D extent) { return create_texture_space_targets(device, extent); }

// What one frame did (read back after the submission).
struct HtexCounters {
  uint32_t marked_groups = 0;        // after any bias
  uint32_t marked_groups_unbiased = 0;
  uint32_t marked_shadels = 0;
  uint32_t bias_levels = 0;          // levels of bias the allocator applied (0: none needed)
  bool overflow = false;             // still more marked groups than pages at the largest bias
  uint32_t unallocated_groups = 0;   // marked groups left without a page
  uint32_t resident_groups = 0;      // groups holding a page after allocation
  uint32_t released_pages = 0;       // given back this frame
  uint32_t allocated_pages = 0;      // taken this frame
  uint32_t free_pages = 0;           // on the free list after allocation
  uint32_t shaded_shadels = 0;       // tasks
  uint32_t shaded_texels = 0;        // texels of the tasks that belong to a quad
  uint32_t reused_shadels = 0;       // marked shadels not shaded again (reuse_shading)
  uint32_t hole_pixels = 0;          // gathered pixels that missed a non-resident texel
  uint64_t pool_bytes = 0;
};

class HtexPass {
 public:
  // `geometry` must outlive the pass. Throws vk::NoSuitableDevice without gl_PrimitiveID in
  // fragment shaders, fragment stores, ray tracing or indirect ray tracing; InputError
  // (the pool-pages setting) for a pool that is empty or beyond the device's buffer or launch limits.
  HtexPass(const vk::Device& device, const HtexGeometry& geometry, const HtexSettings& settings = {});

  // Records the four passes. `scene`, `tlas` and `targets` must outlive the submission; the TLAS
  // must be built relative to scene.origin (rt::SceneAccel's default origin is the same).
  // Leaves targets.color in TRANSFER_SRC_OPTIMAL. One record per submission (the frame's
  // uniforms live in one buffer written now).
  void record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, HtexTargets& targets,
              const Camera& camera, vk::GpuTimer& timer);
  // The same in parts, for a pass that records between shading and gathering (the GI hook).
  void record_marking(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, HtexTargets& targets,
                      const Camera& camera, vk::GpuTimer& timer);
  void record_allocation(VkCommandBuffer cmd, const HtexTargets& targets, vk::GpuTimer& timer);
  void record_shading(VkCommandBuffer cmd, const HtexTargets& targets, vk::GpuTimer& timer);
  void record_gather(VkCommandBuffer cmd, HtexTargets& targets, vk::GpuTimer& timer);

  // Counters of the last recorded frame (after its submission completed).
  HtexCounters read_counters() const;
  // Every page back on the free list, every group non-resident (waits for the device).
  void reset_residency();
  // Forgets which shadels hold valid shading: the next frame shades every marked shadel.
  void invalidate_shading() { invalidate_ = true; }

  const HtexSettings& settings() const { return settings_; }
  void set_settings(const HtexSettings& settings);  // pool_pages and indirect must stay the same
  const HtexGeometry& geometry() const { return geometry_; }
  const HtexTables& tables() const { return tables_; }
  // Buffers for tests and for passes that plug in (all storage buffers).
  const vk::Buffer& occupancy() const { return occupancy_; }
  const vk::Buffer& page_table() const { return page_table_; }
  const vk::Buffer& pool() const { return pool_; }
  const vk::Buffer& indirect_radiance() const { return indirect_; }
  const vk::Buffer& tasks() const { return tasks_; }
  const vk::Buffer& state() const { return state_; }

  // Copies a device buffer to the host (waits for the device): for tests and the CLI.
  std::vector<std::byte> read_buffer(const vk::Buffer& buffer) const;

 private:
  void bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const HtexTargets& targets);
  void push_step(VkCommandBuffer cmd, uint32_t step);
  void dispatch_step(VkCommandBuffer cmd, uint32_t step, uint32_t invocations);

  const vk::Device& device_;
  const HtexGeometry& geometry_;
  HtexSettings settings_;
  HtexTables tables_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline depth_pipeline_, mark_pipeline_, allocate_pipeline_, gather_pipeline_;
  rt::RayTracingPipeline shade_pipeline_;
  vk::DescriptorSet set_;
  vk::Buffer frame_uniforms_;
  vk::Buffer occupancy_, page_table_, free_list_, state_, tasks_, pool_, indirect_, shaded_;
  bool invalidate_ = false;
  vk::Buffer readback_;  // host-visible copy of the state after each frame
  SceneSetBinding bound_;
  VkExtent2D extent_{};
  uint32_t flags_ = 0;
};

// One frame rendered and read back: what the CLI and the tests use.
struct HtexImage : TextureSpaceImage {
  HtexCounters counters;
};
HtexImage render_htex(const vk::Device& device, HtexPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                      const Camera& camera, VkExtent2D extent);

}  // namespace prismoid::surface
