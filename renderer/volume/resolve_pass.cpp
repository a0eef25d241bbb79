#include "renderer/volume/resolve_pass.hpp"

#include <span>

#include "renderer/vk/device.hpp"
#include "renderer/vk/timer.hpp"
#include "shaders/shared/volume.h"

namespace prismoid::volume {

namespace {

const std::array<vk::DescriptorBinding, 4> kResolveBindings = {{
    {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
    {1, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
    {2, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
    {3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT},
}};

}  // namespace

ResolvePass::ResolvePass(const vk::Device& device) : device_(device) {
  set_layout_ = vk::create_descriptor_set_layout(device, kResolveBindings);
  VkDescriptorSetLayout sets[] = {set_layout_.get()};
  VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::ResolvePush)};
  layout_ = vk::create_pipeline_layout(device, sets, std::span(&push, 1));
  pipeline_ = vk::create_compute_pipeline(device, "volume/resolve.comp", layout_.get());
  set_ = vk::allocate_descriptor_set(device, set_layout_.get(), kResolveBindings);
}

void ResolvePass::bind_targets(const VolumeTargets& targets) {
  const std::array<uint64_t, 4> key{targets.optical_depth.serial(), targets.display.serial(), targets.quantity.serial(),
                                    targets.emission.serial()};
  if (key == bound_targets_) return;
  vk::write_storage_image_descriptor(device_, set_.set, 0, targets.optical_depth.view());
  vk::write_storage_image_descriptor(device_, set_.set, 1, targets.display.view());
  vk::write_storage_image_descriptor(device_, set_.set, 2, targets.quantity.view());
  vk::write_storage_image_descriptor(device_, set_.set, 3, targets.emission.view());
  bound_targets_ = key;
}

void ResolvePass::record(VkCommandBuffer cmd, VolumeTargets& targets, const ResolveSettings& settings, AccumulatedBy by,
                         vk::GpuTimer& timer) {
  const bool emission = settings.quantity == Quantity::Color;
  const bool isosurface = settings.quantity == Quantity::Isosurface;
  const bool to_emission = emission || isosurface;
  const vk::Image& target = to_emission ? targets.emission : targets.optical_depth;
  const VkExtent2D e = targets.extent;
  bind_targets(targets);
  {
    vk::ScopedPass pass(timer, cmd, "resolve");
    // The resolve's descriptor set names both accumulation targets; the one this frame did not
    // draw is never read, but must be in the layout the set declares (its contents stay undefined).
    const vk::Image& other = to_emission ? targets.optical_depth : targets.emission;
    vk::image_barrier(cmd, other.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                      VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    if (by == AccumulatedBy::Compute)
      vk::image_barrier(cmd, target.get(), VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                        VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    else
      vk::image_barrier(cmd, target.get(), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                        VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
    for (VkImage image : {targets.display.get(), targets.quantity.get()})
      vk::image_barrier(cmd, image, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
    gpu::ResolvePush push{};
    push.background = glm::vec4(settings.background, 1.0f);
    push.medium = glm::vec4(settings.medium, 1.0f);
    const uint32_t quantity = emission     ? PRISMOID_QUANTITY_COLOR
                              : isosurface ? PRISMOID_QUANTITY_ISOSURFACE
                              : settings.quantity == Quantity::Transmittance ? PRISMOID_QUANTITY_TRANSMITTANCE
                                                                             : PRISMOID_QUANTITY_OPTICAL_DEPTH;
    push.params = glm::uvec4(quantity, e.width, e.height, 0u);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_.set, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (e.width + 7) / 8, (e.height + 7) / 8, 1);
    for (VkImage image : {targets.display.get(), targets.quantity.get(), targets.emission.get()})
      vk::image_barrier(cmd, image, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                        VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT,
                        VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  }
}

}  // namespace prismoid::volume
