#pragma once
// Interval shading of tetrahedral volumes (Tricard 2024): a mesh-shader pass that
// accumulates optical depth per pixel, and a compute pass that resolves it to the
// requested quantity and a display colour.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <tuple>
#include <utility>
#include <glm/vec3.hpp>

#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "renderer/volume/resolve_settings.hpp"
#include "renderer/volume/segment_integral.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::vk {
class Device;
class GpuTimer;
}  // namespace prismoid::vk
namespace prismoid::gpu {
struct FrameUniforms;
}  // namespace prismoid::gpu

namespace prismoid::volume {

// A TetMesh on the GPU. Positions are stored as float relative to `origin` (the mesh's
// bounds centre, kept in double), so far-from-origin data loses no precision. Extinction is
// stored up to volume::extinction_cap of the mesh's diagonal (float_limits.hpp).
struct GpuTetMesh {
  vk::Buffer positions;
  vk::Buffer tets;
  vk::Buffer cell_sigma;
  vk::Buffer point_sigma;  // a stub when sigma is constant per cell
  vk::Buffer cell_scalar;  // the transfer function's scalar per cell (a stub when absent)
  vk::Buffer point_scalar; // ... per point (a stub when absent)
  glm::dvec3 origin{0.0};
  uint32_t tet_count = 0;
  bool linear = false;     // sigma linear per cell, from point_sigma
  bool has_scalars = false;
  bool scalar_per_point = false;
  double longest_edge = 0.0;  // bounds every segment inside a cell (the table's length axis)
  double radius = 0.0;        // no point is farther from `origin` (half the bounds' diagonal)
  double extinction_cap = 0.0;  // extinction above this is stored as this (volume::extinction_cap)
  double scalar_min = 0.0, scalar_max = 0.0;  // the scalar field's range (0, 0 when absent)
};
GpuTetMesh upload(const vk::Device& device, const TetMesh& mesh);

// Images one frame writes: accumulated optical depth, the quantity, the display colour.
struct VolumeTargets {
  vk::Image optical_depth;  // R32F colour attachment, additive blending
  vk::Image emission;       // RGBA32F colour attachment: premultiplied colour, alpha; front to back
  vk::Image quantity;       // R32F: optical depth or transmittance
  vk::Image display;        // RGBA32F linear colour
  vk::Image depth;          // D32: isosurface hits, near / depth (the greater, nearer, wins)
  VkExtent2D extent{};
};
VolumeTargets create_targets(const vk::Device& device, VkExtent2D extent);

// The largest cells-per-workgroup size (kTetletSizes) the device's mesh-output limits allow
// (a near-clipped cell emits up to 15 vertices and 12 triangles).
uint32_t max_tetlet_size(const vk::Device& device);

// Tetlets (renderer/volume/tetlets.hpp) on the GPU, for one cells-per-workgroup size.
struct GpuTetlets {
  vk::Buffer headers;
  vk::Buffer points;
  vk::Buffer cells;
  uint32_t count = 0;      // tetlets: the workgroups to launch
  uint32_t max_cells = 0;  // = the tetlet size they were built for
  double points_per_cell = 0.0;
};
GpuTetlets upload_tetlets(const vk::Device& device, const TetMesh& mesh, uint32_t tetlet_size);

class IntervalShadingPass {
 public:
  explicit IntervalShadingPass(const vk::Device& device);

  // CPU work before recording a frame, outside any command buffer: checks the settings
  // (InputError names the option at fault), makes the pipeline (unless `mesh_pipeline` is
  // false: the compute backend draws the intervals), uploads a marched grid.
  void prepare(const GpuTetMesh& mesh, const ResolveSettings& settings, bool mesh_pipeline = true);
  // Colour: whether the transfer function on the GPU (and with preintegration_size > 0 the
  // table) is the one these settings ask for, for this mesh.
  bool transfer_current(const GpuTetMesh& mesh, const ResolveSettings& settings) const;
  // Uploads the transfer function's breakpoints and builds the pre-integrated table where they
  // differ from the current ones (waits for the device first). Returns the milliseconds spent.
  double upload_transfer(const GpuTetMesh& mesh, const ResolveSettings& settings);

  // Records both passes: record_intervals() then record_resolve(). Cells are drawn in the
  // order of `order` (uint32 cell indices) when given, else in mesh order. Leaves
  // `targets.quantity`, `targets.display` and `targets.emission` in TRANSFER_SRC_OPTIMAL
  // layout. `mesh`, `targets` and `order` must outlive the submission. Colour needs
  // upload_transfer() first.
  void record(VkCommandBuffer cmd, const GpuTetMesh& mesh, VolumeTargets& targets, const Camera& camera,
              const ResolveSettings& settings, vk::GpuTimer& timer, const vk::Buffer* order = nullptr,
              const GpuTetlets* tetlets = nullptr);
  // The interval pass alone (named interval_pass_name(settings)), drawing into the
  // accumulation target; the resolve pass must follow in the same command buffer.
  void record_intervals(VkCommandBuffer cmd, const GpuTetMesh& mesh, VolumeTargets& targets, const Camera& camera,
                        const ResolveSettings& settings, vk::GpuTimer& timer, const vk::Buffer* order = nullptr,
                        const GpuTetlets* tetlets = nullptr);
  // The resolve pass ("resolve"): the quantity and the display colour from what the interval
  // pass just drew.
  void record_resolve(VkCommandBuffer cmd, VolumeTargets& targets, const ResolveSettings& settings, vk::GpuTimer& timer);

  const PreintegrationTable& table() const { return table_; }

  // The compute backend (compute_intervals.hpp) draws the intervals into the same targets
  // instead of record_intervals(), with the storage images in GENERAL layout; the resolve
  // then follows it.
  void intervals_drawn_by_compute();
  // What the interval stages of both backends read: the frame's uniforms (`ordered`: cells are
  // drawn in the order of PRISMOID_BINDING_ORDER), and the buffers of the transfer function,
  // the pre-integrated table and the marched grid (a stub where the frame has none).
  gpu::FrameUniforms frame_uniforms(const GpuTetMesh& mesh, const Camera& camera, VkExtent2D extent,
                                    const ResolveSettings& settings, bool ordered) const;
  const vk::Buffer& transfer_buffer() const { return tf_buffer_.get() != VK_NULL_HANDLE ? tf_buffer_ : stub_; }
  const vk::Buffer& table_buffer() const { return table_buffer_.get() != VK_NULL_HANDLE ? table_buffer_ : stub_; }
  const vk::Buffer& grid_buffer() const { return grid_buffer_.get() != VK_NULL_HANDLE ? grid_buffer_ : stub_; }

  // What the last recorded interval pass drew (pipeline statistics; zeros where the device
  // cannot count): primitives the mesh shader emitted that reached the clipper, and fragments
  // shaded. Waits for the GPU.
  struct DrawCounts {
    uint64_t primitives = 0;
    uint64_t fragments = 0;
  };
  DrawCounts read_counts() const;
  bool counts_draws() const { return statistics_.get() != VK_NULL_HANDLE; }

 private:
  void bind_mesh(const GpuTetMesh& mesh);
  void bind_targets(const VolumeTargets& targets);
  void bind_order(const vk::Buffer* order);
  void upload_grid(const std::shared_ptr<const SampledGrid>& grid);
  // What a frame's fragment stage does: optical depth and emission (exact intervals), the
  // same marched inside intervals, or the nearest isosurface hit.
  enum class PipelineKind { OpticalDepth, Emission, MarchDepth, MarchColor, Isosurface };
  static PipelineKind pipeline_kind(const ResolveSettings& settings);
  VkPipeline pipeline(uint32_t tetlet_size, PipelineKind kind, bool shared_vertices);
  void bind_tetlets(const GpuTetlets* tetlets);

  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout mesh_set_layout_;
  vk::UniquePipelineLayout mesh_layout_;
  // (cells per workgroup, kind) -> pipeline, made on first use.
  std::map<std::tuple<uint32_t, PipelineKind, bool>, vk::UniquePipeline> pipelines_;
  // What the descriptors name, by serials (vk::next_resource_serial; 0: nothing yet).
  std::array<uint64_t, 3> bound_tetlets_{};
  vk::DescriptorSet mesh_set_;
  vk::UniqueDescriptorSetLayout resolve_set_layout_;
  vk::UniquePipelineLayout resolve_layout_;
  vk::UniquePipeline resolve_pipeline_;
  vk::DescriptorSet resolve_set_;
  vk::Buffer frame_uniforms_;
  vk::Buffer stub_;  // bound where a frame has no order or no table
  vk::Buffer depth_limit_;  // per pixel, when the settings end rays at opaque geometry (host-visible)
  PreintegrationTable table_;
  std::vector<TfSample> table_tf_;  // the transfer function of tf_buffer_ and table_
  vk::Buffer tf_buffer_;
  vk::Buffer table_buffer_;
  uint64_t bound_order_ = 0;
  std::shared_ptr<const SampledGrid> grid_;  // the samples in grid_buffer_ (held, so the pointer stays unique)
  vk::Buffer grid_buffer_;                    // bound at PRISMOID_BINDING_FIELD_GRID; the stub until a grid is marched
  vk::UniqueQueryPool statistics_;  // empty where the device has no pipeline statistics
  bool counted_ = false;            // a draw was bracketed since the pool was made
  std::array<uint64_t, 6> bound_mesh_{};
  std::array<uint64_t, 4> bound_targets_{};
  bool intervals_recorded_ = false;  // record_resolve() follows record_intervals()
  bool intervals_by_compute_ = false;  // ... or the compute backend's raster (targets in GENERAL layout)
};

}  // namespace prismoid::volume
