#include "renderer/surface/scene_descriptors.hpp"

#include "shaders/shared/surface.h"

namespace prismoid::surface {

std::vector<vk::DescriptorBinding> scene_bindings(const SceneBindingOptions& o) {
  const VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  std::vector<vk::DescriptorBinding> b = {
      {PRISMOID_SURFACE_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, o.stages},
      {PRISMOID_SURFACE_BINDING_MATERIALS, storage, o.stages},
      {PRISMOID_SURFACE_BINDING_TRIANGLES, storage, o.stages},
      {PRISMOID_SURFACE_BINDING_POINT_LIGHTS, storage, o.stages},
      {PRISMOID_SURFACE_BINDING_DIRECTIONAL_LIGHTS, storage, o.stages},
      {PRISMOID_SURFACE_BINDING_EMITTERS, storage, o.stages},
  };
  if (o.vertex_buffers)
    for (uint32_t binding : {PRISMOID_SURFACE_BINDING_POSITIONS, PRISMOID_SURFACE_BINDING_ATTRIBUTES,
                             PRISMOID_SURFACE_BINDING_INDICES, PRISMOID_SURFACE_BINDING_MESHES})
      b.push_back({binding, storage, o.stages});
  if (o.tlas) b.push_back({PRISMOID_SURFACE_BINDING_TLAS, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, o.stages});
  return b;
}

void write_scene_descriptors(const vk::Device& device, VkDescriptorSet set, const GpuSurfaceScene& scene, bool vertex_buffers) {
  const VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_MATERIALS, storage, scene.materials.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_TRIANGLES, storage, scene.triangles.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_POINT_LIGHTS, storage, scene.point_lights.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_DIRECTIONAL_LIGHTS, storage, scene.directional_lights.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_EMITTERS, storage, scene.emitters.get());
  if (!vertex_buffers) return;
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_POSITIONS, storage, scene.positions.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_ATTRIBUTES, storage, scene.attributes.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_INDICES, storage, scene.indices.get());
  vk::write_buffer_descriptor(device, set, PRISMOID_SURFACE_BINDING_MESHES, storage, scene.meshes.get());
}

rt::RayTracingPipelineDesc surface_rt_pipeline(std::vector<std::string_view> raygen, VkPipelineLayout layout) {
  rt::RayTracingPipelineDesc d;
  d.raygen = std::move(raygen);
  d.miss = {"surface/rt/shadow.rmiss", "surface/rt/hit.rmiss"};  // PRISMOID_SURFACE_MISS_SHADOW, _HIT
  d.hit_groups = {{"surface/rt/hit.rchit", {}}};                  // PRISMOID_SURFACE_HIT_GROUP
  d.layout = layout;
  return d;
}

}  // namespace prismoid::surface
