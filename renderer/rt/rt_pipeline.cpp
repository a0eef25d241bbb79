#include "renderer/rt/rt_pipeline.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/pipeline.hpp"
#include "shaders/registry.hpp"

namespace prismoid::rt {

namespace {

VkDeviceSize align_up(VkDeviceSize value, VkDeviceSize alignment) { return (value + alignment - 1) / alignment * alignment; }
bool power_of_two(uint32_t v) { return v != 0 && (v & (v - 1)) == 0; }

}  // namespace

SbtLayout layout_shader_binding_table(const ShaderGroupProperties& props, uint32_t raygen_count, uint32_t miss_count,
                                      uint32_t hit_count) {
  if (props.handle_size == 0 || !power_of_two(props.handle_alignment) || !power_of_two(props.base_alignment))
    throw std::invalid_argument("shader binding table: the device's shader group handle size and alignments must be "
                                "positive (alignments powers of two)");
  if (raygen_count == 0) throw std::invalid_argument("shader binding table: a pipeline needs a ray-generation shader");
  SbtLayout l;
  const VkDeviceSize record = align_up(props.handle_size, props.handle_alignment);
  VkDeviceSize at = 0;
  auto region = [&](SbtRegion& r, VkDeviceSize stride, uint32_t count) {
    at = align_up(at, props.base_alignment);
    r.offset = at;
    r.stride = stride;
    r.records = count;
    r.size = stride * count;
    at += r.size;
  };
  region(l.raygen, align_up(props.handle_size, std::max(props.handle_alignment, props.base_alignment)), raygen_count);
  region(l.miss, record, miss_count);
  region(l.hit, record, hit_count);
  l.bytes = at;
  return l;
}

RayTracingPipeline::RayTracingPipeline(const vk::Device& device, const RayTracingPipelineDesc& desc) : device_(&device) {
  const auto& caps = device.capabilities();
  if (!device.ray_tracing_enabled())
    throw vk::NoSuitableDevice(caps.name + " has no ray-tracing pipelines enabled (VK_KHR_ray_tracing_pipeline)");
  if (desc.max_recursion_depth > caps.max_ray_recursion_depth)
    throw std::invalid_argument("ray-tracing pipeline: recursion depth " + std::to_string(desc.max_recursion_depth) +
                                " exceeds the device's " + std::to_string(caps.max_ray_recursion_depth));
  layout_ = layout_shader_binding_table({caps.shader_group_handle_size, caps.shader_group_handle_alignment,
                                         caps.shader_group_base_alignment},
                                        static_cast<uint32_t>(desc.raygen.size()), static_cast<uint32_t>(desc.miss.size()),
                                        static_cast<uint32_t>(desc.hit_groups.size()));
  if (std::max({layout_.raygen.stride, layout_.miss.stride, layout_.hit.stride}) > caps.max_shader_group_stride)
    throw vk::NoSuitableDevice(caps.name + ": a shader binding table record exceeds maxShaderGroupStride");

  // Stages, then groups: raygen..., miss..., hit groups..., the order of the table's regions.
  std::vector<vk::UniqueShaderModule> modules;
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  auto add_stage = [&](std::string_view name, VkShaderStageFlagBits stage) -> uint32_t {
    if (name.empty()) return VK_SHADER_UNUSED_KHR;
    modules.push_back(vk::create_shader_module(device, shaders::spirv(name)));
    VkPipelineShaderStageCreateInfo s{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    s.stage = stage;
    s.module = modules.back().get();
    s.pName = "main";
    stages.push_back(s);
    return static_cast<uint32_t>(stages.size() - 1);
  };
  std::vector<VkRayTracingShaderGroupCreateInfoKHR> groups;
  auto general = [&](uint32_t stage) {
    VkRayTracingShaderGroupCreateInfoKHR g{VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR};
    g.type = VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR;
    g.generalShader = stage;
    g.closestHitShader = g.anyHitShader = g.intersectionShader = VK_SHADER_UNUSED_KHR;
    groups.push_back(g);
  };
  for (auto name : desc.raygen) {
    if (name.empty()) throw std::invalid_argument("ray-tracing pipeline: an empty ray-generation shader name");
    general(add_stage(name, VK_SHADER_STAGE_RAYGEN_BIT_KHR));
  }
  for (auto name : desc.miss) {
    if (name.empty()) throw std::invalid_argument("ray-tracing pipeline: an empty miss shader name");
    general(add_stage(name, VK_SHADER_STAGE_MISS_BIT_KHR));
  }
  for (const auto& h : desc.hit_groups) {
    VkRayTracingShaderGroupCreateInfoKHR g{VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR};
    g.type = VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR;
    g.generalShader = g.intersectionShader = VK_SHADER_UNUSED_KHR;
    g.closestHitShader = add_stage(h.closest_hit, VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR);
    g.anyHitShader = add_stage(h.any_hit, VK_SHADER_STAGE_ANY_HIT_BIT_KHR);
    groups.push_back(g);
  }

  VkRayTracingPipelineCreateInfoKHR info{VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR};
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.groupCount = static_cast<uint32_t>(groups.size());
  info.pGroups = groups.data();
  info.maxPipelineRayRecursionDepth = desc.max_recursion_depth;
  info.layout = desc.layout;
  VkPipeline pipeline;
  vk::check(device.create_ray_tracing_pipelines(device.get(), VK_NULL_HANDLE, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
            ("vkCreateRayTracingPipelinesKHR (" + std::string(desc.raygen.front()) + ")").c_str());
  pipeline_ = vk::UniquePipeline(device.get(), pipeline);

  // The table: every group's handle copied to its record.
  const uint32_t handle_size = caps.shader_group_handle_size;
  std::vector<std::byte> handles(size_t(groups.size()) * handle_size);
  vk::check(device.get_ray_tracing_shader_group_handles(device.get(), pipeline, 0, static_cast<uint32_t>(groups.size()),
                                                        handles.size(), handles.data()),
            "vkGetRayTracingShaderGroupHandlesKHR");
  const VkDeviceSize base = caps.shader_group_base_alignment;
  sbt_ = vk::Buffer(device, layout_.bytes + base,
                    VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                    vk::MemoryUse::HostVisible);
  const VkDeviceAddress address = sbt_.device_address();
  sbt_address_ = align_up(address, base);
  std::byte* table = sbt_.mapped() + (sbt_address_ - address);
  std::memset(sbt_.mapped(), 0, sbt_.size());
  uint32_t group = 0;
  for (const SbtRegion* r : {&layout_.raygen, &layout_.miss, &layout_.hit})
    for (uint32_t i = 0; i < r->records; ++i, ++group)
      std::memcpy(table + r->offset + i * r->stride, handles.data() + size_t(group) * handle_size, handle_size);
}

RayTracingPipeline::Regions RayTracingPipeline::regions(uint32_t raygen) const {
  auto region = [&](const SbtRegion& r, VkDeviceSize first, VkDeviceSize size) {
    VkStridedDeviceAddressRegionKHR out{};
    if (r.records == 0) return out;  // an unused region is all zero
    out.deviceAddress = sbt_address_ + r.offset + first;
    out.stride = r.stride;
    out.size = size;
    return out;
  };
  Regions out;
  out.raygen = region(layout_.raygen, raygen * layout_.raygen.stride, layout_.raygen.stride);
  out.miss = region(layout_.miss, 0, layout_.miss.size);
  out.hit = region(layout_.hit, 0, layout_.hit.size);
  return out;
}

void RayTracingPipeline::trace(VkCommandBuffer cmd, uint32_t raygen, uint32_t width, uint32_t height, uint32_t depth) const {
  if (raygen >= layout_.raygen.records)
    throw std::invalid_argument("ray-tracing pipeline: no ray-generation shader " + std::to_string(raygen));
  const uint64_t invocations = uint64_t(width) * height * depth;
  if (invocations > device_->capabilities().max_ray_dispatch_invocations)
    throw std::invalid_argument("ray-tracing launch of " + std::to_string(invocations) + " rays exceeds the device's limit of " +
                                std::to_string(device_->capabilities().max_ray_dispatch_invocations));
  const Regions r = regions(raygen);
  device_->cmd_trace_rays(cmd, &r.raygen, &r.miss, &r.hit, &r.callable, width, height, depth);
}

}  // namespace prismoid::rt

namespace prismoid::rt {

void RayTracingPipeline::trace_indirect(VkCommandBuffer cmd, uint32_t raygen, VkDeviceAddress command) const {
  if (raygen >= layout_.raygen.records)
    throw std::invalid_argument("ray-tracing pipeline: no ray-generation shader " + std::to_string(raygen));
  if (!device_->cmd_trace_rays_indirect)
    throw vk::NoSuitableDevice(device_->capabilities().name + " cannot trace rays with GPU-written launch sizes "
                               "(no rayTracingPipelineTraceRaysIndirect)");
  const Regions r = regions(raygen);
  device_->cmd_trace_rays_indirect(cmd, &r.raygen, &r.miss, &r.hit, &r.callable, command);
}

}  // namespace prismoid::rt
