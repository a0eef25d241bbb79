#pragma once
// Interval shading of tetrahedral volumes (Tricard 2024): a mesh-shader pass that
// accumulates optical depth per pixel, and a compute pass that resolves it to the
// requested quantity and a display colour.
#include <cstdint>
#include <glm/vec3.hpp>

#include "renderer/vk/memory.hpp"
#include "renderer/vk/pipeline.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::vk {
class Device;
class GpuTimer;
}  // namespace prismoid::vk

namespace prismoid::volume {

enum class Quantity { OpticalDepth, Transmittance };

// A TetMesh on the GPU. Positions are stored as float relative to `origin` (the mesh's
// bounds centre, kept in double), so far-from-origin data loses no precision.
struct GpuTetMesh {
  vk::Buffer positions;
  vk::Buffer tets;
  vk::Buffer cell_sigma;
  vk::Buffer point_sigma;  // a stub when sigma is constant per cell
  glm::dvec3 origin{0.0};
  uint32_t tet_count = 0;
  bool linear = false;     // sigma linear per cell, from point_sigma
};
GpuTetMesh upload(const vk::Device& device, const TetMesh& mesh);

// Images one frame writes: accumulated optical depth, the quantity, the display colour.
struct VolumeTargets {
  vk::Image optical_depth;  // R32F colour attachment, additive blending
  vk::Image quantity;       // R32F: optical depth or transmittance
  vk::Image display;        // RGBA32F linear colour
  VkExtent2D extent{};
};
VolumeTargets create_targets(const vk::Device& device, VkExtent2D extent);

struct ResolveSettings {
  Quantity quantity = Quantity::Transmittance;
  glm::vec3 background{1.0f, 1.0f, 1.0f};
  glm::vec3 medium{0.05f, 0.08f, 0.2f};
};

class IntervalShadingPass {
 public:
  explicit IntervalShadingPass(const vk::Device& device);

  // Records both passes. Leaves `targets.quantity` and `targets.display` in
  // TRANSFER_SRC_OPTIMAL layout. `mesh` and `targets` must outlive the submission.
  void record(VkCommandBuffer cmd, const GpuTetMesh& mesh, VolumeTargets& targets, const Camera& camera,
              const ResolveSettings& settings, vk::GpuTimer& timer);

 private:
  void bind_mesh(const GpuTetMesh& mesh);
  void bind_targets(const VolumeTargets& targets);

  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout mesh_set_layout_;
  vk::UniquePipelineLayout mesh_layout_;
  vk::UniquePipeline mesh_pipeline_;
  vk::DescriptorSet mesh_set_;
  vk::UniqueDescriptorSetLayout resolve_set_layout_;
  vk::UniquePipelineLayout resolve_layout_;
  vk::UniquePipeline resolve_pipeline_;
  vk::DescriptorSet resolve_set_;
  vk::Buffer frame_uniforms_;
  const GpuTetMesh* bound_mesh_ = nullptr;
  const VolumeTargets* bound_targets_ = nullptr;
  VkImage bound_optical_depth_ = VK_NULL_HANDLE;
};

}  // namespace prismoid::volume
