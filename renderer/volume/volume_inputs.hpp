#pragma once
// What every volume backend reads (issue "Every volume backend behind one contract"): the mesh
// and its fields on the device, the images a frame writes, and VolumeInputs: the transfer
// function's breakpoints and pre-integrated table, a marched grid's samples, the per-pixel depth
// limit, and the frame's uniforms. Built once per scene change and shared: the mesh-shader pass
// (interval_shading.hpp) and the compute backend (compute_intervals.hpp) both bind these
// buffers, and neither owns anything the other reads. The resolve after either is its own pass
// (resolve_pass.hpp).
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "renderer/vk/memory.hpp"
#include "renderer/volume/resolve_settings.hpp"
#include "renderer/volume/segment_integral.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::vk {
class Device;
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
// Replaces the field buffers (extinction and scalars, per cell and per point) and what is known
// of them with `mesh`'s, whose points and cells must be those `gpu` was uploaded from (a time
// step of a static mesh): positions, cells, the origin and the extinction cap, which depend on
// the geometry alone, stay. The buffers are new (new serials: the backends rebind them); no frame
// reading the old ones may be in flight.
void upload_fields(const vk::Device& device, GpuTetMesh& gpu, const TetMesh& mesh);

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

// The cells-per-workgroup settings every frame is checked against, whichever backend draws it
// (InputError names the option): a tetlet size the mesh shaders are built for, and shared
// vertices only with more than one cell per workgroup.
void check_workgroup_settings(const ResolveSettings& settings);

class VolumeInputs {
 public:
  explicit VolumeInputs(const vk::Device& device);

  // CPU work before a frame, outside any command buffer: checks the colour settings (InputError
  // names the option at fault), uploads a marched grid, writes the depth limit (its size is the
  // frame's, checked by the caller). Waits for the device where it replaces a buffer.
  void prepare(const GpuTetMesh& mesh, const ResolveSettings& settings);
  // Colour: whether the transfer function on the GPU (and with preintegration_size > 0 the
  // table) is the one these settings ask for, for this mesh.
  bool transfer_current(const GpuTetMesh& mesh, const ResolveSettings& settings) const;
  // Uploads the transfer function's breakpoints and builds the pre-integrated table where they
  // differ from the current ones (waits for the device first). Returns the milliseconds spent.
  double upload_transfer(const GpuTetMesh& mesh, const ResolveSettings& settings);
  // Throws std::logic_error where a frame of these settings would read an input not uploaded
  // (colour before upload_transfer, a grid before prepare).
  void check_ready(const ResolveSettings& settings) const;

  // The uniforms of a frame of both backends' interval stages (`ordered`: cells are drawn in the
  // order of PRISMOID_BINDING_ORDER).
  gpu::FrameUniforms frame_uniforms(const GpuTetMesh& mesh, const Camera& camera, VkExtent2D extent, const ResolveSettings& settings,
                                    bool ordered) const;

  // The buffers the backends bind (a stub where the frame has none); their serials
  // (vk::next_resource_serial) change whenever a buffer is replaced.
  const vk::Buffer& transfer_buffer() const { return tf_buffer_.get() != VK_NULL_HANDLE ? tf_buffer_ : stub_; }
  const vk::Buffer& table_buffer() const { return table_buffer_.get() != VK_NULL_HANDLE ? table_buffer_ : stub_; }
  const vk::Buffer& grid_buffer() const { return grid_buffer_.get() != VK_NULL_HANDLE ? grid_buffer_ : stub_; }
  const vk::Buffer& depth_limit_buffer() const { return depth_limit_.get() != VK_NULL_HANDLE ? depth_limit_ : stub_; }
  // A one-texel buffer for bindings a frame does not read.
  const vk::Buffer& stub() const { return stub_; }

  const PreintegrationTable& table() const { return table_; }

 private:
  void upload_grid(const std::shared_ptr<const SampledGrid>& grid);

  const vk::Device& device_;
  vk::Buffer stub_;
  vk::Buffer depth_limit_;  // per pixel, when the settings end rays at opaque geometry (host-visible)
  PreintegrationTable table_;
  std::vector<TfSample> table_tf_;  // the transfer function of tf_buffer_ and table_
  vk::Buffer tf_buffer_;
  vk::Buffer table_buffer_;
  std::shared_ptr<const SampledGrid> grid_;  // the samples in grid_buffer_ (held, so the pointer stays unique)
  vk::Buffer grid_buffer_;
};

}  // namespace prismoid::volume
