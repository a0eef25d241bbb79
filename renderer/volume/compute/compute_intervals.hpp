#pragma once
// The compute-rasterized interval backend: the intervals the mesh-shader pass draws
// (interval_shading.hpp), found instead by compute shaders on every core, into the same
// targets (VolumeTargets' optical-depth and emission images), so that the resolve pass and
// everything after it are shared. Three passes:
//  - "bin-cells": each cell's conservative screen bounds in 8x8-pixel tiles and a depth key;
//    a prefix sum of the pair counts gives each cell its place; (tile, depth key) pairs written.
//  - "tile-sort": the pairs sorted by tile, then depth, with the GPU radix sort, whose count
//    stays on the GPU (GpuRadixSort::record_indirect); then each tile's range of pairs.
//  - "tile-raster": one workgroup per tile; each pixel computes every cell's interval on its
//    own ray and integrates it exactly as the fragment shaders do (the same GLSL functions),
//    colour through a per-pixel k-buffer in exact depth order (shaders/volume/compute/).
//    A tile of more than PRISMOID_CI_CHUNK pairs (PRISMOID_CI_CHUNK_COLOR for colour) is split
//    into chunks rastered by workgroups of their own and merged in chunk order, so one long
//    list does not hold up the frame; cells spanning many tiles are binned a workgroup each.
//
// The key is one 32-bit word, the tile in the high bits and the depth in the rest (at least
// 5 bits are left for depth at 16k x 16k; 15 at 4K): one 4-pass sort, where sorting twice
// (depth, then tile, stably) would take 8 passes and a gather. Quantizing the depth costs no
// exactness: each pixel orders its intervals by their exact entry depths in the k-buffer, and
// the key only needs to bring them in nearly that order.
//
// Recording rules: as VisibilitySort's (record at most once per command buffer, after the GPU
// finished the previous submission that used this object).
#include <cstdint>
#include <map>
#include <memory>
#include <vulkan/vulkan.h>

#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/volume/volume_inputs.hpp"
#include "renderer/volume/resolve_settings.hpp"
#include "renderer/sort/prefix_sum.hpp"
#include "renderer/sort/radix_sort.hpp"
#include "scene/camera.hpp"

namespace prismoid::vk {
class Device;
class GpuTimer;
}  // namespace prismoid::vk

namespace prismoid::volume {

// What the last frame counted on the GPU (read back after it finished).
struct ComputeIntervalStats {
  uint64_t pairs = 0;           // (tile, cell) pairs the cells asked for
  uint64_t sorted = 0;          // pairs written, sorted and drawn (at most the capacity)
  uint64_t inexact_pixels = 0;  // colour: pixels an interval reached nearer than one already composited
  uint64_t big_cells = 0;       // cells binned a workgroup each (more than PRISMOID_CI_BIG_CELL_TILES tiles)
  uint64_t split_tiles = 0;     // tiles rastered in chunks (more than PRISMOID_CI_CHUNK pairs)
  uint64_t chunks = 0;          // the chunks of the split tiles
  uint64_t redone_tiles = 0;    // split tiles rastered again whole (colour out of order across chunks)
  bool complete() const { return pairs == sorted; }
};

class ComputeIntervals {
 public:
  static constexpr uint32_t kKBuffer = 8;  // intervals each pixel holds back to composite in depth order

  explicit ComputeIntervals(const vk::Device& device);
  ~ComputeIntervals();

  // CPU work before recording a frame: checks that this backend renders these settings
  // (InputError naming the option otherwise), and that its buffers for this mesh and image
  // size fit the device (InputError with the bytes needed); (re)allocates them. Waits for the
  // device when it reallocates.
  void prepare(const GpuTetMesh& mesh, const ResolveSettings& settings, VkExtent2D extent);
  // Grows the pair buffers to hold `pairs` pairs (a frame that asked for more drew only the
  // pairs that fit: ComputeIntervalStats::complete() says so), with the same checks.
  void reserve_pairs(uint64_t pairs);

  // The three passes, each timed under its name ("bin-cells", "tile-sort", "tile-raster"), in
  // this order in one command buffer, for the settings and size prepare() saw. `inputs` holds
  // what both backends read (transfer function, table, grid, depth limit), prepared for these
  // settings. record_raster() leaves the target in GENERAL layout for the resolve pass
  // (resolve_pass.hpp, AccumulatedBy::Compute), which follows it.
  void record_bin(VkCommandBuffer cmd, const GpuTetMesh& mesh, const VolumeInputs& inputs, const VolumeTargets& targets,
                  const Camera& camera, const ResolveSettings& settings, vk::GpuTimer& timer);
  void record_sort(VkCommandBuffer cmd, vk::GpuTimer& timer);
  void record_raster(VkCommandBuffer cmd, VolumeTargets& targets, vk::GpuTimer& timer);

  // The last recorded frame's counts; call only after the GPU finished it.
  ComputeIntervalStats read_stats() const;
  bool recorded() const { return recorded_; }

  // Device memory the backend holds now (pair and sort buffers, per-cell bins and offsets,
  // tile ranges), and what a frame of `cells` cells, `tiles` tiles and `pairs` pairs needs.
  uint64_t bytes() const;
  static uint64_t bytes_for(uint64_t cells, uint64_t tiles, uint64_t pairs);
  uint64_t pair_capacity() const { return pair_capacity_; }

 private:
  void allocate(uint64_t cells, uint64_t tiles, uint64_t pairs);
  void check_fits(uint64_t cells, uint64_t tiles, uint64_t pairs) const;
  void bind_frame_inputs(const GpuTetMesh& mesh, const VolumeInputs& inputs, const VolumeTargets& targets);

  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline bin_count_, bin_emit_, big_emit_, tile_ranges_, tile_chunks_, chunk_args_, tile_merge_;
  std::map<uint32_t, vk::UniquePipeline> tile_rasters_;  // by PRISMOID_CI_* mode, made in prepare() on first use
  vk::DescriptorSet set_;
  // The prefix sum of the pair counts runs the radix sort's scan kernels on these bindings.
  std::unique_ptr<sort::GpuPrefixSum> scan_;  // the pair counts into each cell's first pair
  std::unique_ptr<sort::GpuRadixSort> sort_;

  vk::Buffer frame_uniforms_;  // gpu::FrameUniforms (host-visible)
  vk::Buffer stats_;           // uint[PRISMOID_CI_STAT_COUNT], counted on the GPU
  vk::Buffer stats_readback_;  // their copy in host memory, read after the frame
  vk::Buffer bins_, offsets_;
  vk::Buffer keys_, values_;
  vk::Buffer tile_ranges_buffer_;
  vk::Buffer big_cells_;                          // per cell (at most every cell is big)
  vk::Buffer chunk_base_, split_tiles_;           // per tile
  vk::Buffer chunk_work_, partials_;              // per chunk slot (chunk_capacity_)
  uint64_t cell_capacity_ = 0, tile_capacity_ = 0, pair_capacity_ = 0, chunk_capacity_ = 0;
  uint64_t mesh_bytes_ = 0;  // the mesh's own buffers (they share the device's memory)

  // The frame prepare() saw, for the record calls.
  struct Frame;
  std::unique_ptr<Frame> frame_;
  bool recorded_ = false;
};

}  // namespace prismoid::volume
