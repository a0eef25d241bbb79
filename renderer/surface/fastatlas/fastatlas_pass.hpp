#pragma once
// FastAtlas (Real-Time Compact Atlases for Texture Space Shading, 2024) on the GPU: every frame a
// new atlas of what is visible, built in compute passes, shaded by the shared shading code and
// looked up with the hard-edge filter. Per frame:
//  - "pre-z + visibility": the depth pre-pass, then an EQUAL-tested pass (visible.frag) that
//    marks each triangle holding a pixel's sample (one entry per triangle) and stores the pixel's
//    triangle and weights for the lookup.
//  - "atlasing": charts (vertices.comp, hook.comp: a union-find over shared edges and welded
//    vertices, rooted at each chart's lowest triangle), boxes (boxes.comp: each triangle's screen
//    box clipped at the near plane alone, folded into its root's; chart_list.comp), order (two
//    stable GPU radix sorts: by root, then by turned height: the paper's deterministic pre-order,
//    measured in place of its bucketed cuckoo hashing), packing (pack.comp: every candidate scale
//    at once, then the largest that fits laid out again), the triangle-ID atlas (clear.comp over
//    the rows used, claim.comp: texels at pixel centres take the visibility pass's triangle, then
//    raster.comp and raster_chunks.comp twice, in compute: each chart's
//    visible triangles covered by their own screen projection where the packer placed them, the
//    nearest depth kept, then its triangle; fa_raster.glsl) and
//    its borders (seeds.comp gives each triangle the raster left without a texel one, border.comp
//    the ring around). Each of these is timed apart (atlas_timings()).
//  - "shading": one ray-generation invocation per texel of the rows used (fa_shade.glsl).
//  - "lookup": per pixel, its chart's map into the atlas and the hard-edge-filtered taps.
// The CPU twins: fastatlas::visible_charts, triangle_box, pack_atlas, chart_map, hard_edge_filter.
// The same frame twice gives the same atlas bit for bit: every step's result is independent of
// the order its invocations run in (minima, sorted lists, scans).
//
// Deviations, each measured or tested: visibility is per sample, not conservative (lavapipe has
// no VK_EXT_conservative_rasterization); borders come from a compute pass rather than a second
// conservative raster (for the same reason); the fold's row capacity is W - widest (atlas_packing.hpp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/fastatlas/scene_adjacency.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/surface/texture_space_passes.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/vk/timer.hpp"
#include "renderer/sort/radix_sort.hpp"
#include "scene/camera.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

struct FastAtlasSettings {
  uint32_t atlas_width = 4096, atlas_height = 4096;  // texels; the width a power of two
  double shading_scale = 1.0;                        // SF: texels per pixel side at the largest candidate
  bool shadows = true;
  bool reuse = false;  // keep the last frame's shading (the atlas is the same: nothing moved)
  // Temporal reuse across a moving camera (the paper's appendix D): 0 off; n: every n-th frame
  // shades every texel, the frames between take a texel's shading from the last frame's atlas
  // where the last frame shaded the same surface point's triangle there (view-dependent terms then
  // lag by up to n - 1 frames: the paper's approximation). Off for scenes of 2^24 triangles or more.
  uint32_t refresh = 0;
  // Chunks the ID atlas raster may list for large triangles (0: twice the atlas's area in chunks).
  // A triangle past the list is covered by one invocation instead, slower and the same texels; a
  // small list makes tests take that path.
  uint32_t raster_chunks = 0;
};

// Empty when the device can run FastAtlas, else why not.
std::string fastatlas_device_problem(const vk::Device& device);

struct FastAtlasCounters {
  uint32_t charts = 0;
  uint32_t visible_triangles = 0;
  bool fits = false;            // some candidate scale fits
  uint32_t candidate = 0;       // the chosen one (0: the largest)
  double scale = 0.0;           // its texels per pixel side
  uint32_t rows_used = 0;       // atlas rows the charts reach
  uint32_t shaded_texels = 0;   // texels shaded this frame (0 when reused)
  uint32_t reused_texels = 0;   // texels taken from the last frame's atlas (temporal reuse)
  bool temporal = false;        // this frame took shading from the last one where it could
  uint32_t border_texels = 0;   // texels the border pass filled
  uint32_t hole_pixels = 0;     // pixels without a usable texel
  // Sander's stretch between screen and atlas over the looked-up pixels, measured as for the
  // other atlases (shaders/surface/stretch.glsl): L2 and L-infinity, both 1 / scale.
  double stretch_l2 = 0.0, stretch_linf = 0.0;
  uint64_t atlas_bytes = 0;     // the atlas images and the per-frame buffers
};

class FastAtlasPass {
 public:
  // Throws vk::NoSuitableDevice (fastatlas_device_problem) and InputError for an atlas the
  // device cannot hold.
  FastAtlasPass(const vk::Device& device, const SurfaceScene& scene, const FastAtlasSettings& settings = {});

  // Records the four passes; leaves targets.color in TRANSFER_SRC_OPTIMAL. One record per
  // submission. The TLAS must be built relative to scene.origin.
  void record(VkCommandBuffer cmd, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, TextureSpaceTargets& targets,
              const Camera& camera, vk::GpuTimer& timer);

  FastAtlasCounters read_counters() const;
  // The atlasing steps' GPU times of the last frame (charts, boxes, order, packing, id raster, borders).
  std::vector<vk::PassTiming> atlas_timings() const { return atlas_timer_.read(); }
  const FastAtlasSettings& settings() const { return settings_; }
  // The next frame shades every texel (temporal reuse starts over).
  void forget_last_frame() { last_frame_.reset(); }
  void set_settings(const FastAtlasSettings& settings);
  const fastatlas::SceneAdjacency& adjacency() const { return adjacency_; }

  // For tests: buffers and atlases of the last frame, read back (waits for the device).
  std::vector<uint32_t> read_parent() const;       // per triangle: its chart's root, or NONE
  std::vector<glm::ivec4> read_boxes() const;      // per triangle (roots): x0, y0, -x1, -y1
  std::vector<glm::uvec4> read_placed() const;     // per triangle (roots): x, y, width | turned << 31, height
  std::vector<uint32_t> read_sorted_charts() const;  // the packing order (roots)
  std::vector<uint32_t> read_id_atlas() const;     // per texel, row-major
  std::vector<glm::vec4> read_color_atlas() const;
  const std::vector<uint32_t>& scale_numerators() const { return scales_; }

 private:
  void bind(const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas, const TextureSpaceTargets& targets);
  // Binds a compute pipeline with the set and this frame's push constants (pass.x = `pass`).
  void bind_compute(VkCommandBuffer cmd, VkPipeline pipeline, uint32_t pass);
  void dispatch(VkCommandBuffer cmd, VkPipeline pipeline, uint32_t groups, uint32_t pass);
  // An indirect dispatch whose group counts a pass left in the state buffer at `state_offset`.
  void dispatch_indirect(VkCommandBuffer cmd, VkPipeline pipeline, VkDeviceSize state_offset, uint32_t pass = 0);

  const vk::Device& device_;
  fastatlas::SceneAdjacency adjacency_;
  FastAtlasSettings settings_;
  uint32_t triangles_ = 0, vertices_ = 0;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline depth_pipeline_, visible_pipeline_, claim_pipeline_, raster_pipeline_, raster_chunks_pipeline_, lookup_pipeline_, clear_pipeline_;
  vk::UniquePipeline vertices_pipeline_, hook_pipeline_, boxes_pipeline_, chart_list_pipeline_, height_keys_pipeline_, pack_pipeline_,
      seeds_pipeline_, border_pipeline_;
  rt::RayTracingPipeline shade_pipeline_;
  vk::DescriptorSet set_;
  vk::Buffer frame_uniforms_, triangle_table_, parent_, vertex_first_, boxes_, keys_, charts_, placed_, candidates_, front_, state_,
      scales_buffer_, history_, visible_, readback_, prev_parent_, prev_boxes_, prev_placed_, prev_state_, prev_frame_,
      chunks_;  // the ID atlas raster's chunks of large triangles (chunk_capacity_ of them)
  uint32_t chunk_capacity_ = 0;
  vk::Image id_atlas_, depth_atlas_, color_atlas_;  // R32_UINT, R32_UINT (depth bits), RGBA32F: storage images
  vk::Image prev_color_;                            // temporal reuse: the last frame's colour atlas (1 x 1 when off)
  vk::UniquePipeline copy_pipeline_;
  std::optional<gpu::SurfaceFrame> last_frame_;     // temporal reuse: the last frame's camera
  uint32_t frames_since_refresh_ = 0;
  bool temporal_ = false;                           // the last recorded frame's
  std::vector<uint32_t> scales_;
  // Two sorts, as a GpuRadixSort updates its descriptor sets when recorded: once per command buffer.
  sort::GpuRadixSort sort_by_root_, sort_by_height_;
  mutable vk::GpuTimer atlas_timer_;
  std::array<std::byte, 48> frame_push_{};  // this frame's FaPush (the compute dispatches change only pass.x)
  SceneSetBinding bound_;
};

// One frame rendered and read back: what the tests use.
struct FastAtlasImage : TextureSpaceImage {
  FastAtlasCounters counters;
};
FastAtlasImage render_fastatlas(const vk::Device& device, FastAtlasPass& pass, const GpuSurfaceScene& scene, VkAccelerationStructureKHR tlas,
                                const Camera& camera, VkExtent2D extent);

}  // namespace prismoid::surface
