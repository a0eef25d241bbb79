#include "renderer/surface/gpu_surface_scene.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "renderer/vk/device.hpp"
#include "scene/input_error.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

template <typename T>
std::span<const std::byte> bytes_of(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

bool positive(const glm::dvec3& v) { return v.x > 0.0 || v.y > 0.0 || v.z > 0.0; }

// Storage buffers cannot be empty: an absent list gets one unused, zeroed entry.
template <typename T>
vk::Buffer storage(const vk::Device& device, std::vector<T> items, uint64_t& bytes) {
  if (items.empty()) items.resize(1);
  bytes += items.size() * sizeof(T);
  return vk::upload_buffer(device, bytes_of(items), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
}

glm::dvec3 winding_normal(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double* area = nullptr) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double len = glm::length(n);
  if (!(len > 0.0) || !std::isfinite(len)) return glm::dvec3(0.0);
  if (area) *area = 0.5 * len;
  return n / len;
}

}  // namespace

GpuSurfaceScene upload(const vk::Device& device, const SurfaceScene& scene) {
  validate(scene);
  validate_float_range(scene);  // radiance is uploaded and summed in float32
  GpuSurfaceScene gpu;
  const Bounds bounds = bounds_of(scene);
  gpu.origin = bounds.center();
  {
    const glm::dvec3 half = bounds.max - gpu.origin;
    gpu.scale = std::max(std::abs(half.x), std::max(std::abs(half.y), std::abs(half.z)));
  }
  gpu.sky = scene.sky;
  const glm::dvec3 o = gpu.origin;

  std::vector<glm::vec3> positions, attributes;
  std::vector<uint32_t> indices;
  std::vector<gpu::SurfaceTriangleGpu> triangles;
  std::vector<gpu::EmitterGpu> emitters;
  std::vector<gpu::SurfaceMeshGpu> meshes;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const SceneMesh& mesh = scene.meshes[m];
    const auto base = static_cast<uint32_t>(positions.size());
    const glm::dvec3& emission = scene.materials[mesh.material].emission;
    meshes.push_back({glm::uvec4(static_cast<uint32_t>(triangles.size()), static_cast<uint32_t>(mesh.triangles.size()), base,
                                 mesh.material)});
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      positions.emplace_back(mesh.positions[v] - o);
      glm::dvec3 n(0.0);
      if (!mesh.normals.empty()) {
        const double len = glm::length(mesh.normals[v]);
        if (len > 0.0 && std::isfinite(len)) n = mesh.normals[v] / len;
      }
      attributes.emplace_back(n);
      attributes.emplace_back(mesh.color_binding == ColorBinding::PerVertex ? glm::vec3(mesh.colors[v]) : glm::vec3(1.0f));
    }
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      for (uint32_t k : tri) indices.push_back(base + k);
      const auto& p = mesh.positions;
      double area = 0.0;
      const glm::dvec3 n = winding_normal(p[tri[0]], p[tri[1]], p[tri[2]], &area);
      gpu::SurfaceTriangleGpu g{};
      g.normal = glm::vec4(glm::vec3(n), 0.0f);
      g.color = glm::vec4(mesh.color_binding == ColorBinding::PerTriangle ? glm::vec3(mesh.colors[t]) : glm::vec3(1.0f), 1.0f);
      g.info = glm::uvec4(mesh.material, m, t, 0u);
      if (positive(emission) && area > 0.0) {
        gpu::EmitterGpu e{};
        e.v0 = glm::vec4(glm::vec3(p[tri[0]] - o), 1.0f);
        e.v1 = glm::vec4(glm::vec3(p[tri[1]] - o), 1.0f);
        e.v2 = glm::vec4(glm::vec3(p[tri[2]] - o), 1.0f);
        e.emission = glm::vec4(glm::vec3(emission), float(area));
        e.normal = glm::vec4(glm::vec3(n), 0.0f);
        e.info = glm::uvec4(static_cast<uint32_t>(triangles.size()), 0u, 0u, 0u);
        emitters.push_back(e);
      }
      triangles.push_back(g);
    }
  }
  const uint64_t triangle_bytes = uint64_t(triangles.size()) * sizeof(gpu::SurfaceTriangleGpu);
  if (triangle_bytes > device.capabilities().max_storage_buffer_range)
    throw InputError(scene.name, std::to_string(triangles.size()) + " triangles exceed the storage-buffer range of " +
                                     device.capabilities().name);

  std::vector<gpu::SurfaceMaterialGpu> materials;
  for (const SurfaceMaterial& m : scene.materials) {
    gpu::SurfaceMaterialGpu g{};
    const double alpha = std::max(m.roughness * m.roughness, kMinGgxAlpha);
    g.albedo = glm::vec4(glm::vec3(m.albedo), float(alpha));
    g.specular = glm::vec4(glm::vec3(m.specular_f0), m.specular_f0 != glm::dvec3(0.0) ? 1.0f : 0.0f);
    g.emission = glm::vec4(glm::vec3(m.emission), 0.0f);
    materials.push_back(g);
  }
  std::vector<gpu::PointLightGpu> points;
  for (const PointLight& l : scene.point_lights)
    points.push_back({glm::vec4(glm::vec3(l.position - o), 1.0f), glm::vec4(glm::vec3(l.intensity), 0.0f)});
  std::vector<gpu::DirectionalLightGpu> directionals;
  for (const DirectionalLight& l : scene.directional_lights)
    directionals.push_back({glm::vec4(glm::vec3(-glm::normalize(l.direction)), 0.0f), glm::vec4(glm::vec3(l.irradiance), 0.0f)});

  const VkBufferUsageFlags vertex = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  if (positions.empty()) positions.resize(1);  // storage buffers cannot be empty (vertex_count stays 0)
  if (indices.empty()) indices.resize(3);
  gpu.positions = vk::upload_buffer(device, bytes_of(positions), vertex);
  attributes.resize(std::max<size_t>(attributes.size(), 2));
  gpu.attributes = vk::upload_buffer(device, bytes_of(attributes), vertex);
  gpu.indices = vk::upload_buffer(device, bytes_of(indices), VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  gpu.bytes = (positions.size() + attributes.size()) * sizeof(glm::vec3) + indices.size() * sizeof(uint32_t);
  gpu.vertex_count = 0;
  for (const SceneMesh& mesh : scene.meshes) gpu.vertex_count += static_cast<uint32_t>(mesh.positions.size());
  gpu.triangle_count = static_cast<uint32_t>(triangles.size());
  gpu.point_light_count = static_cast<uint32_t>(points.size());
  gpu.directional_light_count = static_cast<uint32_t>(directionals.size());
  gpu.emitter_count = static_cast<uint32_t>(emitters.size());
  gpu.materials = storage(device, std::move(materials), gpu.bytes);
  gpu.triangles = storage(device, std::move(triangles), gpu.bytes);
  gpu.point_lights = storage(device, std::move(points), gpu.bytes);
  gpu.directional_lights = storage(device, std::move(directionals), gpu.bytes);
  gpu.emitters = storage(device, std::move(emitters), gpu.bytes);
  gpu.meshes = storage(device, std::move(meshes), gpu.bytes);
  return gpu;
}

SceneBufferKey buffer_key(const GpuSurfaceScene& s) {
  return {s.positions.serial(), s.attributes.serial(), s.indices.serial(), s.meshes.serial(), s.materials.serial(),
          s.triangles.serial(), s.point_lights.serial(), s.directional_lights.serial(), s.emitters.serial()};
}

}  // namespace prismoid::surface
