#pragma once
// The scene's bindings of descriptor set 0 (shaders/shared/surface.h), shared by every surface
// backend's passes so that they shade from the same buffers: a backend lists these plus its
// own (from PRISMOID_SURFACE_BINDING_BACKEND on) and writes the scene's with
// write_scene_descriptors. The TLAS binding is written by the ray-tracing side
// (rt::write_tlas_descriptor), since a GpuSurfaceScene has no acceleration structure.
#include <vector>

#include <string_view>

#include "renderer/rt/rt_pipeline.hpp"
#include "renderer/surface/gpu_surface_scene.hpp"
#include "renderer/vk/pipeline.hpp"

namespace prismoid::surface {

struct SceneBindingOptions {
  VkShaderStageFlags stages = 0;  // stages that read the scene (frame uniforms, materials, lights, ...)
  bool vertex_buffers = false;    // positions, attributes, indices and meshes as storage buffers
  bool tlas = false;              // the acceleration structure (ray-traced passes)
};
std::vector<vk::DescriptorBinding> scene_bindings(const SceneBindingOptions& options);

// Writes the materials, triangles, lights and emitters (and with vertex_buffers the vertex,
// index and mesh buffers); the frame uniforms, the TLAS and a backend's own bindings are the
// caller's.
void write_scene_descriptors(const vk::Device& device, VkDescriptorSet set, const GpuSurfaceScene& scene, bool vertex_buffers);

// A ray-tracing pipeline of the surface passes: these ray-generation shaders, then the miss
// shaders and the hit group in the order shaders/shared/surface.h names them
// (PRISMOID_SURFACE_MISS_SHADOW, PRISMOID_SURFACE_MISS_HIT, PRISMOID_SURFACE_HIT_GROUP).
rt::RayTracingPipelineDesc surface_rt_pipeline(std::vector<std::string_view> raygen, VkPipelineLayout layout);

}  // namespace prismoid::surface
