#include "renderer/volume/compute/compute_intervals.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>

#include "renderer/vk/compute_barrier.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/timer.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/compute_intervals.h"
#include "shaders/shared/sort.h"
#include "shaders/shared/volume.h"

namespace prismoid::volume {

static_assert(ComputeIntervals::kKBuffer == PRISMOID_CI_KBUFFER);

namespace {

constexpr VkDescriptorType kStorage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
constexpr VkShaderStageFlags kCompute = VK_SHADER_STAGE_COMPUTE_BIT;

const std::array<vk::DescriptorBinding, 24> kBindings = {{
    {PRISMOID_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kCompute},
    {PRISMOID_BINDING_POSITIONS, kStorage, kCompute},
    {PRISMOID_BINDING_TETS, kStorage, kCompute},
    {PRISMOID_BINDING_CELL_SIGMA, kStorage, kCompute},
    {PRISMOID_BINDING_POINT_SIGMA, kStorage, kCompute},
    {PRISMOID_BINDING_CELL_SCALAR, kStorage, kCompute},
    {PRISMOID_BINDING_POINT_SCALAR, kStorage, kCompute},
    {PRISMOID_BINDING_PREINTEGRATED, kStorage, kCompute},
    {PRISMOID_BINDING_TRANSFER, kStorage, kCompute},
    {PRISMOID_BINDING_FIELD_GRID, kStorage, kCompute},
    {PRISMOID_CI_BINDING_BINS, kStorage, kCompute},
    {PRISMOID_CI_BINDING_OFFSETS, kStorage, kCompute},
    {PRISMOID_CI_BINDING_KEYS, kStorage, kCompute},
    {PRISMOID_CI_BINDING_VALUES, kStorage, kCompute},
    {PRISMOID_CI_BINDING_TILE_RANGES, kStorage, kCompute},
    {PRISMOID_CI_BINDING_STATS, kStorage, kCompute},
    {PRISMOID_CI_BINDING_OPTICAL_DEPTH, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kCompute},
    {PRISMOID_CI_BINDING_EMISSION, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kCompute},
    {PRISMOID_CI_BINDING_BIG_CELLS, kStorage, kCompute},
    {PRISMOID_CI_BINDING_CHUNK_BASE, kStorage, kCompute},
    {PRISMOID_CI_BINDING_CHUNK_WORK, kStorage, kCompute},
    {PRISMOID_CI_BINDING_SPLIT_TILES, kStorage, kCompute},
    {PRISMOID_CI_BINDING_PARTIALS, kStorage, kCompute},
    {PRISMOID_CI_BINDING_DEPTH_LIMIT, kStorage, kCompute},
}};

// The dispatch-size minimum every device offers, per dimension; also the most blocks the
// sort and the prefix sum (1024 entries each) can take.
constexpr uint64_t kMaxGroups = 65535;
const uint64_t kMaxScanned = sort::GpuPrefixSum::max_count();
constexpr uint64_t kMaxPairs = kMaxGroups * PRISMOID_SORT_BLOCK;

uint32_t groups_for(uint64_t items, uint64_t per_group) {
  return static_cast<uint32_t>(std::clamp<uint64_t>((items + per_group - 1) / per_group, 1, kMaxGroups));
}

// Indirect dispatch arguments written by a kernel, read by the dispatch after it.
void compute_to_indirect(VkCommandBuffer cmd, VkBuffer buffer) {
  vk::buffer_barrier(cmd, {buffer}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
}

// Chunk slots for a pair capacity: a split tile holds more than a chunk (at least
// PRISMOID_CI_CHUNK pairs), so its ceil(n / CHUNK) chunks are at most 2n / CHUNK, and all split
// tiles' at most twice the pairs over CHUNK.
uint64_t chunk_slots_for(uint64_t pairs) { return 2 * pairs / PRISMOID_CI_CHUNK + 1; }

std::string mib(uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MiB"; }

// The reference's tie-break direction for a ray in a face plane (reference/tet_ray.cpp).
const glm::dvec3 kTieBreak(0.5773502691896258, 0.2113248654051871, 0.7886751345948129);

// The tile raster's variant for each mode (tile_raster_*.comp).
const char* raster_shader(uint32_t mode) {
  switch (mode) {
    case PRISMOID_CI_OPTICAL_DEPTH: return "volume/compute/tile_raster_depth.comp";
    case PRISMOID_CI_EMISSION: return "volume/compute/tile_raster_emission.comp";
    case PRISMOID_CI_MARCH_DEPTH: return "volume/compute/tile_raster_march_depth.comp";
    case PRISMOID_CI_MARCH_COLOR: return "volume/compute/tile_raster_march_color.comp";
    case PRISMOID_CI_ISOSURFACE: return "volume/compute/tile_raster_isosurface.comp";
  }
  throw std::logic_error("ComputeIntervals: no tile raster for mode " + std::to_string(mode));
}

uint32_t mode_of(const ResolveSettings& settings) {
  if (settings.march.enabled) {
    if (settings.quantity == Quantity::Color) return PRISMOID_CI_MARCH_COLOR;
    if (settings.quantity == Quantity::Isosurface) return PRISMOID_CI_ISOSURFACE;
    return PRISMOID_CI_MARCH_DEPTH;
  }
  return settings.quantity == Quantity::Color ? PRISMOID_CI_EMISSION : PRISMOID_CI_OPTICAL_DEPTH;
}

}  // namespace

struct ComputeIntervals::Frame {
  VkExtent2D extent{};
  uint32_t tiles_x = 0, tiles_y = 0;
  uint32_t depth_bits = 0;
  uint32_t cells = 0;
  uint32_t mode = PRISMOID_CI_OPTICAL_DEPTH;
  bool depth_limited = false;  // the settings end rays at a depth per pixel
  gpu::ComputeIntervalsPush push{};
};

ComputeIntervals::ComputeIntervals(const vk::Device& device) : device_(device), frame_(std::make_unique<Frame>()) {
  set_layout_ = vk::create_descriptor_set_layout(device, kBindings);
  VkDescriptorSetLayout sets[] = {set_layout_.get()};
  VkPushConstantRange push{kCompute, 0, sizeof(gpu::ComputeIntervalsPush)};
  layout_ = vk::create_pipeline_layout(device, sets, std::span(&push, 1));
  bin_count_ = vk::create_compute_pipeline(device, "volume/compute/bin_count.comp", layout_.get());
  bin_emit_ = vk::create_compute_pipeline(device, "volume/compute/bin_emit.comp", layout_.get());
  tile_ranges_ = vk::create_compute_pipeline(device, "volume/compute/tile_ranges.comp", layout_.get());
  big_emit_ = vk::create_compute_pipeline(device, "volume/compute/big_emit.comp", layout_.get());
  tile_chunks_ = vk::create_compute_pipeline(device, "volume/compute/tile_chunks.comp", layout_.get());
  chunk_args_ = vk::create_compute_pipeline(device, "volume/compute/chunk_args.comp", layout_.get());
  tile_merge_ = vk::create_compute_pipeline(device, "volume/compute/tile_merge.comp", layout_.get());
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), kBindings);
  scan_ = std::make_unique<sort::GpuPrefixSum>(device);

  frame_uniforms_ = vk::Buffer(device, sizeof(gpu::FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, vk::MemoryUse::HostVisible);
  stats_ = vk::Buffer(device, PRISMOID_CI_STAT_COUNT * sizeof(uint32_t),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                          VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                      vk::MemoryUse::DeviceLocal);
  stats_readback_ = vk::Buffer(device, stats_.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  std::memset(stats_readback_.mapped(), 0, stats_readback_.size());
  sort_ = std::make_unique<sort::GpuRadixSort>(device, 1);
}

ComputeIntervals::~ComputeIntervals() = default;

uint64_t ComputeIntervals::bytes_for(uint64_t cells, uint64_t tiles, uint64_t pairs) {
  const uint64_t per_cell = cells * (sizeof(glm::uvec4) + 2 * sizeof(uint32_t)) + sort::GpuPrefixSum::bytes_for(cells);
  const uint64_t per_pair = pairs * 2 * sizeof(uint32_t) + sort::GpuRadixSort::scratch_bytes(static_cast<uint32_t>(std::min(pairs, kMaxPairs)));
  const uint64_t per_chunk = chunk_slots_for(pairs) * (sizeof(glm::uvec2) + PRISMOID_CI_TILE_PIXELS * sizeof(gpu::ChunkPartial));
  return per_cell + tiles * (sizeof(glm::uvec2) + 2 * sizeof(uint32_t)) + per_pair + per_chunk + sizeof(gpu::FrameUniforms) + 2 * PRISMOID_CI_STAT_COUNT * sizeof(uint32_t);
}

uint64_t ComputeIntervals::bytes() const {
  uint64_t total = sort_->bytes() + scan_->bytes();
  for (const vk::Buffer* b : {&frame_uniforms_, &stats_, &stats_readback_, &bins_, &offsets_,
                              &keys_, &values_, &tile_ranges_buffer_, &big_cells_, &chunk_base_, &chunk_work_,
                              &split_tiles_, &partials_})
    total += b->size();
  return total;
}

void ComputeIntervals::check_fits(uint64_t cells, uint64_t tiles, uint64_t pairs) const {
  const auto& caps = device_.capabilities();
  const std::string what = std::to_string(cells) + " cells, " + std::to_string(tiles) + " tiles and " + std::to_string(pairs) +
                           " cell-tile pairs";
  if (cells > kMaxScanned)
    throw InputError(setting("volume-backend", "compute"), "bins at most " + std::to_string(kMaxScanned) + " cells per frame, the mesh has " +
                                                     std::to_string(cells));
  if (pairs > kMaxPairs)
    throw InputError(setting("volume-backend", "compute"), "this frame needs " + what + ", more than the " + std::to_string(kMaxPairs) +
                                                     " pairs one GPU radix sort takes; use a smaller image or " + setting("volume-backend", "mesh"));
  // The largest single buffers: the per-cell bins and the per-pair keys, values and scratch.
  const uint64_t largest = std::max(cells * sizeof(glm::uvec4), pairs * sizeof(uint32_t));
  if (largest > caps.max_storage_buffer_range)
    throw InputError(setting("volume-backend", "compute"), "this frame needs " + what + ": a buffer of " + mib(largest) + ", and " + caps.name +
                                                     " allows " + mib(caps.max_storage_buffer_range) + " per storage buffer");
  const uint64_t needed = bytes_for(cells, tiles, pairs);
  if (caps.device_local_bytes > 0 && needed + mesh_bytes_ > caps.device_local_bytes)
    throw InputError(setting("volume-backend", "compute"), "this frame needs " + mib(needed) + " of device memory for " + what +
                                                     " beside the mesh's " + mib(mesh_bytes_) + "; " + caps.name + " has " +
                                                     mib(caps.device_local_bytes));
}

void ComputeIntervals::allocate(uint64_t cells, uint64_t tiles, uint64_t pairs) {
  cells = std::max<uint64_t>(cells, 1);
  tiles = std::max<uint64_t>(tiles, 1);
  pairs = std::max<uint64_t>(pairs, 1);
  if (cells <= cell_capacity_ && tiles <= tile_capacity_ && pairs <= pair_capacity_) return;
  device_.wait_idle();  // the old buffers may still be read by a frame in flight
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  if (cells > cell_capacity_) {
    bins_ = vk::Buffer(device_, cells * sizeof(glm::uvec4), usage, vk::MemoryUse::DeviceLocal);
    offsets_ = vk::Buffer(device_, cells * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
    scan_->reserve(cells);
    big_cells_ = vk::Buffer(device_, cells * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
    cell_capacity_ = cells;
  }
  if (tiles > tile_capacity_) {
    tile_ranges_buffer_ =
        vk::Buffer(device_, tiles * sizeof(glm::uvec2), usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::DeviceLocal);
    chunk_base_ = vk::Buffer(device_, tiles * sizeof(uint32_t), usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::DeviceLocal);
    split_tiles_ = vk::Buffer(device_, tiles * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
    tile_capacity_ = tiles;
  }
  if (pairs > pair_capacity_) {
    keys_ = vk::Buffer(device_, pairs * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
    values_ = vk::Buffer(device_, pairs * sizeof(uint32_t), usage, vk::MemoryUse::DeviceLocal);
    sort_->reserve(static_cast<uint32_t>(pairs));
    pair_capacity_ = pairs;
    chunk_capacity_ = chunk_slots_for(pairs);
    chunk_work_ = vk::Buffer(device_, chunk_capacity_ * sizeof(glm::uvec2), usage, vk::MemoryUse::DeviceLocal);
    partials_ = vk::Buffer(device_, chunk_capacity_ * PRISMOID_CI_TILE_PIXELS * sizeof(gpu::ChunkPartial), usage,
                           vk::MemoryUse::DeviceLocal);
  }
}

void ComputeIntervals::reserve_pairs(uint64_t pairs) {
  if (pairs <= pair_capacity_) return;
  // A quarter more than asked for, so a camera moving closer does not grow the buffers every frame.
  const uint64_t grown = std::max(pairs, std::min(pairs + pairs / 4, kMaxPairs));
  check_fits(cell_capacity_, tile_capacity_, pairs);
  uint64_t with_room = grown;
  try {
    check_fits(cell_capacity_, tile_capacity_, grown);
  } catch (const InputError&) {
    with_room = pairs;
  }
  allocate(cell_capacity_, tile_capacity_, with_room);
}

void ComputeIntervals::prepare(const GpuTetMesh& mesh, const ResolveSettings& settings, VkExtent2D extent) {
  if (extent.width == 0 || extent.height == 0) throw std::invalid_argument("ComputeIntervals: an empty image");
  Frame& f = *frame_;
  f.extent = extent;
  f.tiles_x = (extent.width + PRISMOID_CI_TILE - 1) / PRISMOID_CI_TILE;
  f.tiles_y = (extent.height + PRISMOID_CI_TILE - 1) / PRISMOID_CI_TILE;
  // Pixel bounds are packed in 16 bits per coordinate (PRISMOID_CI_BINDING_BINS).
  if (extent.width > 65535 || extent.height > 65535)
    throw InputError(setting("volume-backend", "compute"), "draws at most 65535 pixels per side");
  const uint64_t tiles = uint64_t(f.tiles_x) * f.tiles_y;
  // The tile in the high bits of the key, with room for one index past every tile (the key
  // bin_emit.comp writes for a pair it drops), so the depth never fills all 32.
  const uint32_t tile_bits = static_cast<uint32_t>(std::bit_width(tiles));
  f.depth_bits = 32 - tile_bits;
  f.cells = mesh.tet_count;
  f.mode = mode_of(settings);
  auto& raster = tile_rasters_[f.mode];
  if (raster.get() == VK_NULL_HANDLE) raster = vk::create_compute_pipeline(device_, raster_shader(f.mode), layout_.get());
  mesh_bytes_ = 0;
  for (const vk::Buffer* b : {&mesh.positions, &mesh.tets, &mesh.cell_sigma, &mesh.point_sigma, &mesh.cell_scalar, &mesh.point_scalar})
    mesh_bytes_ += b->size();
  check_fits(f.cells, tiles, 0);
  uint64_t pairs = pair_capacity_;
  if (pairs == 0) {
    // A first guess: most cells of a mesh seen whole fall in one or two tiles. A frame that
    // needs more says so (ComputeIntervalStats) and the pairs grow to what it needed.
    pairs = std::min<uint64_t>(std::max<uint64_t>(2 * uint64_t(f.cells) + tiles, 1u << 16), kMaxPairs);
    try {
      check_fits(f.cells, tiles, pairs);
    } catch (const InputError&) {
      pairs = f.cells;
    }
  }
  check_fits(f.cells, tiles, pairs);
  allocate(f.cells, tiles, pairs);
  // Where each pixel's ray ends (opaque geometry): VolumeInputs holds it, of the frame's size.
  f.depth_limited = settings.depth_limit != nullptr;
  if (f.depth_limited && settings.depth_limit->size() != size_t(extent.width) * extent.height)
    throw InputError("depth limit", "has " + std::to_string(settings.depth_limit->size()) + " values for a " +
                                        std::to_string(extent.width) + "x" + std::to_string(extent.height) + " frame");
}

void ComputeIntervals::bind_frame_inputs(const GpuTetMesh& mesh, const VolumeInputs& inputs, const VolumeTargets& targets) {
  // Written on every frame, not cached: the recording rule guarantees no frame reads the set.
  const VkDescriptorSet s = set_.set;
  vk::write_buffer_descriptor(device_, s, PRISMOID_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame_uniforms_.get());
  const std::pair<uint32_t, const vk::Buffer*> buffers[] = {
      {PRISMOID_BINDING_POSITIONS, &mesh.positions},       {PRISMOID_BINDING_TETS, &mesh.tets},
      {PRISMOID_BINDING_CELL_SIGMA, &mesh.cell_sigma},     {PRISMOID_BINDING_POINT_SIGMA, &mesh.point_sigma},
      {PRISMOID_BINDING_CELL_SCALAR, &mesh.cell_scalar},   {PRISMOID_BINDING_POINT_SCALAR, &mesh.point_scalar},
      {PRISMOID_BINDING_PREINTEGRATED, &inputs.table_buffer()}, {PRISMOID_BINDING_TRANSFER, &inputs.transfer_buffer()},
      {PRISMOID_BINDING_FIELD_GRID, &inputs.grid_buffer()}, {PRISMOID_CI_BINDING_BINS, &bins_},
      {PRISMOID_CI_BINDING_OFFSETS, &offsets_},            {PRISMOID_CI_BINDING_KEYS, &keys_},
      {PRISMOID_CI_BINDING_VALUES, &values_},              {PRISMOID_CI_BINDING_TILE_RANGES, &tile_ranges_buffer_},
      {PRISMOID_CI_BINDING_STATS, &stats_},                {PRISMOID_CI_BINDING_BIG_CELLS, &big_cells_},
      {PRISMOID_CI_BINDING_CHUNK_BASE, &chunk_base_},      {PRISMOID_CI_BINDING_CHUNK_WORK, &chunk_work_},
      {PRISMOID_CI_BINDING_SPLIT_TILES, &split_tiles_},    {PRISMOID_CI_BINDING_PARTIALS, &partials_},
      {PRISMOID_CI_BINDING_DEPTH_LIMIT, &inputs.depth_limit_buffer()},
  };
  for (const auto& [binding, buffer] : buffers) vk::write_buffer_descriptor(device_, s, binding, kStorage, buffer->get());
  vk::write_storage_image_descriptor(device_, s, PRISMOID_CI_BINDING_OPTICAL_DEPTH, targets.optical_depth.view());
  vk::write_storage_image_descriptor(device_, s, PRISMOID_CI_BINDING_EMISSION, targets.emission.view());
}

void ComputeIntervals::record_bin(VkCommandBuffer cmd, const GpuTetMesh& mesh, const VolumeInputs& inputs, const VolumeTargets& targets,
                                  const Camera& camera, const ResolveSettings& settings, vk::GpuTimer& timer) {
  Frame& f = *frame_;
  if (mesh.tet_count != f.cells || mode_of(settings) != f.mode)
    throw std::logic_error("ComputeIntervals: record_bin() for another mesh or quantity than prepare() saw");
  if (targets.extent.width != f.extent.width || targets.extent.height != f.extent.height)
    throw std::logic_error("ComputeIntervals: record_bin() for another image size than prepare() saw");
  // Every descriptor of the frame is written here, before its command buffer binds the set.
  inputs.check_ready(settings);
  bind_frame_inputs(mesh, inputs, targets);
  const gpu::FrameUniforms frame = inputs.frame_uniforms(mesh, camera, f.extent, settings, false);
  frame_uniforms_.write(std::as_bytes(std::span(&frame, 1)));
  // The depth key: the nearest depth of a cell's part beyond the near plane, minus the mesh
  // origin's, over the range the mesh can span, in (2^depth_bits - 1) steps.
  const glm::dmat4 view = view_matrix(camera, mesh.origin);
  const double near_from_origin = camera.near_distance + view[3][2];
  const double lo = std::max(-mesh.radius, near_from_origin), hi = mesh.radius;
  const double keys = std::ldexp(1.0, int(f.depth_bits)) - 1.0;
  gpu::ComputeIntervalsPush& push = f.push;
  push.tiles = glm::uvec4(f.tiles_x, f.tiles_y, f.depth_bits, static_cast<uint32_t>(pair_capacity_));
  push.depth = glm::vec4(float(lo), hi > lo ? float(keys / (hi - lo)) : 0.0f, 0.0f, 0.0f);
  push.tie_break = glm::vec4(glm::vec3(glm::dmat3(view) * kTieBreak), 0.0f);
  push.options = glm::uvec4(f.mode, f.extent.width, f.extent.height, f.depth_limited ? 1u : 0u);
  const bool colour = f.mode == PRISMOID_CI_EMISSION || f.mode == PRISMOID_CI_MARCH_COLOR;
  push.chunks = glm::uvec4(static_cast<uint32_t>(chunk_capacity_), PRISMOID_CI_LAUNCH_TILES,
                           colour ? PRISMOID_CI_CHUNK_COLOR : PRISMOID_CI_CHUNK, 0u);

  vk::ScopedPass pass(timer, cmd, "bin-cells");
  // The last frame's tile raster and read back are done with the counts.
  vk::buffer_barrier(cmd, {stats_.get()}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_NONE,
                     VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(cmd, stats_.get(), 0, VK_WHOLE_SIZE, 0u);
  vk::buffer_barrier(cmd, {stats_.get()}, VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  if (f.cells == 0) return;
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), kCompute, 0, sizeof(push), &push);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, bin_count_.get());
  vkCmdDispatch(cmd, groups_for(f.cells, PRISMOID_CI_WORKGROUP), 1, 1);
  vk::compute_to_compute(cmd, {bins_.get(), offsets_.get(), big_cells_.get(), stats_.get()});

  // Prefix sum of the pair counts, in place: each cell's first pair.
  scan_->record(cmd, offsets_, static_cast<uint32_t>(f.cells));

  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), kCompute, 0, sizeof(push), &push);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, bin_emit_.get());
  vkCmdDispatch(cmd, groups_for(f.cells, PRISMOID_CI_WORKGROUP), 1, 1);
  // The big cells' pairs, a workgroup each, as many as bin_emit.comp's last cell asked for.
  compute_to_indirect(cmd, stats_.get());
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, big_emit_.get());
  vkCmdDispatchIndirect(cmd, stats_.get(), PRISMOID_CI_ARGS_BIG_EMIT * sizeof(uint32_t));
}

void ComputeIntervals::record_sort(VkCommandBuffer cmd, vk::GpuTimer& timer) {
  const Frame& f = *frame_;
  vk::ScopedPass pass(timer, cmd, "tile-sort");
  // The sort waits for the pairs and their count (compute writes) itself.
  sort_->record_indirect(cmd, keys_, values_, stats_, PRISMOID_CI_STAT_SORTED, static_cast<uint32_t>(pair_capacity_));
  // Tiles hold no pairs and are not split until the kernels below say otherwise.
  vk::buffer_barrier(cmd, {tile_ranges_buffer_.get(), chunk_base_.get()}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_NONE,
                     VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  vkCmdFillBuffer(cmd, tile_ranges_buffer_.get(), 0, VK_WHOLE_SIZE, 0u);
  vkCmdFillBuffer(cmd, chunk_base_.get(), 0, VK_WHOLE_SIZE, PRISMOID_CI_UNSPLIT);
  vk::buffer_barrier(cmd, {tile_ranges_buffer_.get(), chunk_base_.get()}, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                     VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                     VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  if (f.cells == 0) return;
  vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
  vkCmdPushConstants(cmd, layout_.get(), kCompute, 0, sizeof(f.push), &f.push);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tile_ranges_.get());
  vkCmdDispatch(cmd, groups_for(pair_capacity_, PRISMOID_CI_WORKGROUP), 1, 1);
  // Tiles with long lists are split into chunks, and the dispatches that raster and merge
  // them sized.
  vk::compute_to_compute(cmd, {tile_ranges_buffer_.get()});
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tile_chunks_.get());
  vkCmdDispatch(cmd, groups_for(uint64_t(f.tiles_x) * f.tiles_y, PRISMOID_CI_WORKGROUP), 1, 1);
  vk::compute_to_compute(cmd, {stats_.get()});
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, chunk_args_.get());
  vkCmdDispatch(cmd, 1, 1, 1);
}

void ComputeIntervals::record_raster(VkCommandBuffer cmd, VolumeTargets& targets, vk::GpuTimer& timer) {
  const Frame& f = *frame_;
  if (targets.extent.width != f.extent.width || targets.extent.height != f.extent.height)
    throw std::logic_error("ComputeIntervals: record_raster() for another image size than prepare() saw");
  {
    vk::ScopedPass pass(timer, cmd, "tile-raster");
    vk::compute_to_compute(cmd, {tile_ranges_buffer_.get(), chunk_base_.get(), chunk_work_.get(), split_tiles_.get()});
    compute_to_indirect(cmd, stats_.get());
    // Both accumulation images are named by the set; the one this frame does not write keeps
    // undefined contents (the resolve never reads it), like the mesh-shader pass's.
    for (VkImage image : {targets.optical_depth.get(), targets.emission.get()})
      vk::image_barrier(cmd, image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), kCompute, 0, sizeof(f.push), &f.push);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tile_rasters_.at(f.mode).get());
    vkCmdDispatch(cmd, f.tiles_x, f.tiles_y, 1);
    // The split tiles' other chunks (none in most frames), then their merge.
    gpu::ComputeIntervalsPush chunks = f.push;
    chunks.chunks.y = PRISMOID_CI_LAUNCH_CHUNKS;
    vkCmdPushConstants(cmd, layout_.get(), kCompute, 0, sizeof(chunks), &chunks);
    vkCmdDispatchIndirect(cmd, stats_.get(), PRISMOID_CI_ARGS_CHUNKS * sizeof(uint32_t));
    vk::compute_to_compute(cmd, {partials_.get()});
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tile_merge_.get());
    vkCmdDispatchIndirect(cmd, stats_.get(), PRISMOID_CI_ARGS_MERGE * sizeof(uint32_t));
    if (f.mode == PRISMOID_CI_EMISSION || f.mode == PRISMOID_CI_MARCH_COLOR) {
      // Split tiles whose colour the merge could not put in each pixel's order, whole.
      vk::compute_to_compute(cmd, {split_tiles_.get()});
      chunks.chunks.y = PRISMOID_CI_LAUNCH_REDO;
      vkCmdPushConstants(cmd, layout_.get(), kCompute, 0, sizeof(chunks), &chunks);
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, tile_rasters_.at(f.mode).get());
      vkCmdDispatchIndirect(cmd, stats_.get(), PRISMOID_CI_ARGS_MERGE * sizeof(uint32_t));
    }
    // The counts go to host memory for read_stats().
    vk::buffer_barrier(cmd, {stats_.get()}, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
    const VkBufferCopy region{0, 0, stats_.size()};
    vkCmdCopyBuffer(cmd, stats_.get(), stats_readback_.get(), 1, &region);
    vk::buffer_barrier(cmd, {stats_readback_.get()}, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT);
  }
  recorded_ = true;
}

ComputeIntervalStats ComputeIntervals::read_stats() const {
  uint32_t values[PRISMOID_CI_STAT_COUNT];
  std::memcpy(values, stats_readback_.mapped(), sizeof(values));
  ComputeIntervalStats s;
  s.pairs = values[PRISMOID_CI_STAT_PAIRS];
  s.sorted = values[PRISMOID_CI_STAT_SORTED];
  s.inexact_pixels = values[PRISMOID_CI_STAT_INEXACT];
  s.big_cells = values[PRISMOID_CI_STAT_BIG_CELLS];
  s.split_tiles = values[PRISMOID_CI_STAT_SPLIT_TILES];
  s.redone_tiles = values[PRISMOID_CI_STAT_REDO_TILES];
  s.chunks = values[PRISMOID_CI_STAT_SPLIT_TILES] + values[PRISMOID_CI_STAT_EXTRA_CHUNKS];
  return s;
}

}  // namespace prismoid::volume
