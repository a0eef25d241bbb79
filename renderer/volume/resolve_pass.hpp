#pragma once
// The resolve after either volume backend's interval stage: from the accumulated optical depth
// (or premultiplied emission, or isosurface hits) to the frame's quantity and display colour
// (shaders/volume/resolve.comp). Its own pass, so that neither backend owns what the other runs
// after it.
#include <array>
#include <cstdint>

#include <vulkan/vulkan.h>

#include "renderer/vk/pipeline.hpp"
#include "renderer/volume/resolve_settings.hpp"
#include "renderer/volume/volume_inputs.hpp"

namespace prismoid::vk {
class Device;
class GpuTimer;
}  // namespace prismoid::vk

namespace prismoid::volume {

// How the interval stage left its accumulation target: a colour attachment (the mesh-shader
// pass) or a storage image in GENERAL layout (the compute backend).
enum class AccumulatedBy { Raster, Compute };

class ResolvePass {
 public:
  explicit ResolvePass(const vk::Device& device);

  // Records "resolve": the quantity and the display colour from what the interval stage just
  // drew into `targets` in the same command buffer. Leaves `targets.quantity`, `targets.display`
  // and `targets.emission` in TRANSFER_SRC_OPTIMAL layout.
  void record(VkCommandBuffer cmd, VolumeTargets& targets, const ResolveSettings& settings, AccumulatedBy by, vk::GpuTimer& timer);

 private:
  void bind_targets(const VolumeTargets& targets);

  const vk::Device& device_;
  vk::UniqueDescriptorSetLayout set_layout_;
  vk::UniquePipelineLayout layout_;
  vk::UniquePipeline pipeline_;
  vk::DescriptorSet set_;
  std::array<uint64_t, 4> bound_targets_{};
};

}  // namespace prismoid::volume
