#pragma once
// Interval shading of tetrahedral volumes (Tricard 2024): the mesh-shader backend, a pass that
// accumulates each pixel's intervals (optical depth, emission, marched samples or isosurface hits)
// from what every backend reads (volume_inputs.hpp); the resolve pass follows it (resolve_pass.hpp).
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
#include "renderer/volume/volume_inputs.hpp"
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

  // CPU work before recording a frame, outside any command buffer: checks the cells-per-workgroup
  // settings against the device (InputError names the option at fault) and makes the pipeline.
  void prepare(const ResolveSettings& settings);

  // Records the interval pass (named interval_pass_name(settings)) into the accumulation
  // target, reading `inputs` (prepared for these settings). Cells are drawn in the order of
  // `order` (uint32 cell indices) when given, else in mesh order, or as `tetlets` group them.
  // The resolve pass (resolve_pass.hpp, AccumulatedBy::Raster) must follow in the same command
  // buffer. `mesh`, `inputs`, `targets` and `order` must outlive the submission.
  void record(VkCommandBuffer cmd, const GpuTetMesh& mesh, const VolumeInputs& inputs, VolumeTargets& targets, const Camera& camera,
              const ResolveSettings& settings, vk::GpuTimer& timer, const vk::Buffer* order = nullptr,
              const GpuTetlets* tetlets = nullptr);

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
  void bind_inputs(const VolumeInputs& inputs);
  void bind_order(const vk::Buffer* order);
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
  vk::Buffer frame_uniforms_;
  vk::Buffer stub_;  // bound where a frame has no order and no tetlets
  uint64_t bound_order_ = 0;
  vk::UniqueQueryPool statistics_;  // empty where the device has no pipeline statistics
  bool counted_ = false;            // a draw was bracketed since the pool was made
  std::array<uint64_t, 6> bound_mesh_{};
  std::array<uint64_t, 4> bound_inputs_{};
};

}  // namespace prismoid::volume
