#pragma once
// A scene on the GPU with everything the Htex pass needs (GPU scene, acceleration structure,
// Htex geometry, the pass), and read-backs of the pass's buffers, for the Htex tests.
#include <cstring>
#include <memory>
#include <vector>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/surface/htex_pass.hpp"
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
