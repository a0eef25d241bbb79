#pragma once
// The meshlet shading atlas backend (Neff et al. 2022, "Meshlets and How to Shade Them: A Study
// on Texture-Space Shading") over the meshlets and charts of meshlets.hpp (the paper's
// pre-charted variant, MSA-UV, with planar charts). Per frame:
//  - "pre-z + visibility": with per-frame charts (MSA-P, MSA-O) first every meshlet's chart from
//    this frame's camera (frame_charts.comp); a depth pre-pass, then an EQUAL-tested pass once per visible pixel
//    (shaders/surface/msa/mark.frag): the pixel's barycentric weights to a visibility buffer;
//    its meshlet marked seen with the density it wants (texels per chart unit so that a texel
//    is at most a pixel: the maximum over the meshlet's pixels).
//  - "block management" (compute, allocate.comp): each seen meshlet's block size (its chart's
//    rectangle at that density, a texel of border per side, powers of two, scaled down by the
//    shading budget when one is set); blocks of meshlets no longer seen or changing size are
//    released; superblocks (256 x 256 texels, one block size each) are claimed from the pool for
//    what the released slots cannot serve; new blocks allocated; the tiles of blocks to shade
//    queued. Everything runs on the GPU, in parallel over meshlets or block sizes.
//  - "shading": ONE ray-generation shader (shade.rgen; shade_unshadowed.rgen without shadows),
//    8 x 8 invocations per queued tile: texel -> chart point -> its triangle (or the nearest
//    within sqrt(2) texels: the dilation for bilinear taps) -> the shared shading code.
//  - "display": a full-screen pass: per pixel, its chart point through its meshlet's block,
//    bilinear by hand from the atlas.
//
// Shading is reused while a meshlet keeps its block: always for a still eye (the planner's
// rule), and with temporal amortization (`shade_every` n) held blocks are shaded again only every
// n-th frame whatever the camera does (new blocks at once), the paper's 4.5 experiment.
//
// Deviations from the paper: planar charts rather than LSCM; one block size (not one width)
// per superblock, and superblocks go back to the pool only when the atlas is reset (after it
// ran out); shading in a ray-generation shader (shadow rays without ray queries) rather than
// rasterizing meshlets into the atlas; visibility from a triangle-id pre-pass rather than a
// meshlet-id buffer (the same information).
#include <cstdint>
#include <string>
#include <vector>

#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/msa/meshlets.hpp"
#include "renderer/surface/texture_space_passes.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/camera.hpp"

namespace prismoid::surface {

struct MsaSettings {
  uint32_t superblocks = 64;      // the atlas: this many 256 x 256 superblocks (1 MiB of RGBA32F each)
  bool shadows = true;
  uint32_t budget_texels = 0;     // shading budget per frame (block texels); 0: none
  // Temporal amortization n: every n-th frame shades every held block again; in between only new
  // blocks are shaded. 0: held blocks are shaded again only after invalidate_shading() (the
  // caller's rule: a moved eye), which keeps the image exact.
  uint32_t shade_every = 0;
  // Projection or Conformal: the meshlets' static charts (MeshletSet::corner_chart). Perspective or
  // Orthographic: charts made every frame from the camera (frame_charts.comp, in the visibility
  // pass), MSA-P and MSA-O; the caller shades again whenever the view changes.
  msa::Parametrization frame_charts = msa::Parametrization::Projection;
};

std::string msa_device_problem(const vk::Device& device);

// Visibility per pixel: triangle + 1 (0: sky), 0, b1 and b2 as float bits.
using MsaTargets = TextureSpaceTargets;
inline MsaTargets create_msa_targets(const vk::Device& device, VkExtent2D extent) { return create_texture_space_targets(device, extent); }

struct MsaCounters {
  uint32_t seen_meshlets = 0;
  uint32_t allocated_blocks = 0;   // this frame
  uint32_t released_blocks = 0;    // this frame
  uint32_t shaded_blocks = 0;
  uint32_t shaded_tiles = 0;
  uint32_t shading_launch = 0;     // the shading launch's depth (z): tiles / PRISMOID_MSA_TILES_PER_LAUNCH, rounded up
  uint32_t shaded_texels = 0;      // texels of shaded tiles inside a meshlet (with its dilation)
  uint32_t free_superblocks = 0;
  bool out_of_superblocks = false;
  uint32_t meshlets_without_block = 0;
  uint32_t hole_pixels = 0;        // pixels drawn without any shaded tap
  uint64_t demand_texels = 0;      // block texels wanted before the budget
  uint64_t held_texels = 0;        // block texels of the seen meshlets after allocation
  float budget_factor = 1.0f;
  // Sander's stretch between screen and atlas over the displayed pixels (shaders/surface/stretch.glsl):
  // L2 (root mean square) and L-infinity (largest); 0 when no pixel was measured.
  double stretch_l2 = 0.0, stretch_linf = 0.0;
  uint64_t atlas_bytes = 0;
};

// Block-size arithmetic (the twins of shaders/surface/msa/msa.glsl), in meshlets.hpp.
using msa::msa_block_scale;
using msa::msa_class_for;
using msa::msa_class_size;

class MsaPass {
 public:
  MsaPass(const vk::Device& device, const msa::MeshletSet& meshlets, const MsaSettings& settings = {});

  void record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, MsaTargets& targets, const Camera& camera,
              vk::GpuTimer& timer);
  MsaCounters read_counters() const;
  // The next frame shades every seen meshlet's block.
  void invalidate_shading() { invalidate_ = true; }
  // Every block and superblock back to the pool (waits for the device); done by record() itself
  // after a frame that ran out of superblocks.
  void reset_atlas();
  const MsaSettings& settings() const { return settings_; }
  void set_settings(const MsaSettings& settings);  // superblocks must stay the same
  const msa::MeshletSet& meshlets() const { return meshlets_; }
  uint32_t atlas_width() const;
  uint32_t atlas_height() const;
  const vk::Buffer& blocks() const { return blocks_; }
  const vk::Buffer& triangle_table() const { return triangles_; }  // MsaTriangleGpu per triangle: the charts in use
  const vk::Buffer& meshlet_table() const { return meshlet_table_; }  // MsaMeshletGpu per meshlet
  const vk::Buffer& density() const { return density_; }
  const vk::Buffer& result() const { return result_; }
  const vk::Buffer& tasks() const { return tasks_; }
  std::vector<std::byte> read_buffer(const vk::Buffer& buffer) const;

 private:
  void bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const MsaTargets& targets);

  const vk::Device& device_;
  const msa::MeshletSet& meshlets_;
  MsaSettings settings_;
  uint32_t columns_ = 1, rows_ = 1;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline depth_pipeline_, mark_pipeline_, display_pipeline_, allocate_pipeline_, frame_charts_pipeline_;
  rt::RayTracingPipeline shade_pipeline_;
  vk::DescriptorSet set_;
  vk::Buffer frame_uniforms_, triangles_, meshlet_table_, meshlet_triangles_, blocks_, density_, classes_, class_superblocks_, free_slots_,
      pool_, state_, tasks_, result_, readback_;
  uint32_t frame_stamp_ = 0;
  uint32_t frames_since_shading_ = 0;
  bool invalidate_ = false;
  SceneSetBinding bound_;
};

struct MsaImage : TextureSpaceImage {
  MsaCounters counters;
};
MsaImage render_msa(const vk::Device& device, MsaPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const Camera& camera,
                    VkExtent2D extent);

}  // namespace prismoid::surface
