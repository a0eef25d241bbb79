#pragma once
// A scene on the GPU with everything the Htex pass needs (GPU scene, acceleration structure,
// Htex geometry, the pass), and read-backs of the pass's buffers, for the Htex tests.
#include <cstring>
#include <memory>
#include <vector>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/htex/htex_pass.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/pipeline.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::test {

struct HtexRig {
  HtexRig(const vk::Device& device, SurfaceScene s, const htex::LayoutOptions& layout, const surface::HtexSettings& settings)
      : scene(std::move(s)),
        gpu(surface::upload(device, scene)),
        accel(device, scene),
        geometry(scene, layout),
        pass(std::make_unique<surface::HtexPass>(device, geometry, settings)) {}

  surface::HtexImage render(const vk::Device& device, const Camera& camera, uint32_t w, uint32_t h) {
    return surface::render_htex(device, *pass, gpu, accel.tlas(), camera, {w, h});
  }
  template <typename T>
  std::vector<T> read(const vk::Buffer& buffer) const {
    const std::vector<std::byte> bytes = pass->read_buffer(buffer);
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
    return out;
  }
  // The mesh and the triangle within it of a global triangle.
  std::pair<uint32_t, uint32_t> local_triangle(uint32_t global) const {
    uint32_t mesh = 0;
    while (mesh + 1 < geometry.first_triangle.size() && geometry.first_triangle[mesh + 1] <= global) ++mesh;
    return {mesh, global - geometry.first_triangle[mesh]};
  }

  SurfaceScene scene;
  surface::GpuSurfaceScene gpu;
  rt::SceneAccel accel;
  surface::HtexGeometry geometry;
  std::unique_ptr<surface::HtexPass> pass;
};

// Runs one of the Htex GLSL-twin compute shaders (surface/htex/*_test.comp): the atlas tables at
// their bindings, `queries` at binding 40, one Result per query at 41, the query count as the
// push constant, one invocation per query. Returns the results.
template <typename Result, typename Query>
std::vector<Result> run_htex_twin_shader(const vk::Device& device, const surface::HtexTables& tables, const char* shader,
                                         const std::vector<Query>& queries) {
  std::vector<vk::DescriptorBinding> bindings = surface::htex_table_bindings(VK_SHADER_STAGE_COMPUTE_BIT);
  bindings.push_back({40, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_COMPUTE_BIT});
  bindings.push_back({41, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_SHADER_STAGE_COMPUTE_BIT});
  auto set_layout = vk::create_descriptor_set_layout(device, bindings);
  const VkDescriptorSetLayout sl = set_layout.get();
  const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, 4};
  auto layout = vk::create_pipeline_layout(device, std::span(&sl, 1), std::span(&push, 1));
  auto pipeline = vk::create_compute_pipeline(device, shader, layout.get());
  const vk::DescriptorSet set = vk::allocate_descriptor_set(device, sl, bindings);
  surface::write_htex_table_descriptors(device, set.set, tables);
  const vk::Buffer qbuf = vk::upload_buffer(device, std::as_bytes(std::span(queries)), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  const vk::Buffer rbuf(device, queries.size() * sizeof(Result), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUse::HostVisible);
  vk::write_buffer_descriptor(device, set.set, 40, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, qbuf.get());
  vk::write_buffer_descriptor(device, set.set, 41, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, rbuf.get());
  const auto count = static_cast<uint32_t>(queries.size());
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline.get());
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout.get(), 0, 1, &set.set, 0, nullptr);
    vkCmdPushConstants(cmd, layout.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, 4, &count);
    vkCmdDispatch(cmd, (count + 63) / 64, 1, 1);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT, VK_PIPELINE_STAGE_2_HOST_BIT,
                       VK_ACCESS_2_HOST_READ_BIT);
  });
  std::vector<Result> results(queries.size());
  std::memcpy(results.data(), rbuf.mapped(), results.size() * sizeof(Result));
  return results;
}

// The weights the GPU stored for a pixel, widened as the gather rebuilds them (w0 = 1 - w1 - w2 in float).
inline glm::dvec3 stored_barycentrics(const glm::uvec4& vis) {
  float b1, b2;
  std::memcpy(&b1, &vis.z, 4);
  std::memcpy(&b2, &vis.w, 4);
  volatile float b0 = 1.0f - b1 - b2;
  volatile float v1 = b1, v2 = b2;
  return {static_cast<double>(b0), static_cast<double>(v1), static_cast<double>(v2)};
}

}  // namespace prismoid::test
