#pragma once
// A SurfaceScene on the GPU, in the layouts of shaders/shared/surface.h: every mesh in one
// vertex and index buffer (drawn with one call, so gl_PrimitiveID is the global triangle
// index), per-triangle data, materials and lights. Positions are float relative to `origin`
// (the scene's bounds centre, kept in double), so a scene far from the world origin keeps its
// precision. Every surface backend shades from these buffers.
#include <array>
#include <cstdint>

#include <glm/vec3.hpp>

#include "renderer/vk/memory.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::vk {
class Device;
}

namespace prismoid::surface {

struct GpuSurfaceScene {
  vk::Buffer positions;           // vec3 per vertex (vertex binding 0)
  vk::Buffer attributes;          // normal vec3, colour vec3 per vertex (vertex binding 1)
  vk::Buffer indices;             // uint32, 3 per triangle, already offset to the shared vertex buffer
  // positions, attributes and indices are also storage buffers (surface_point.glsl reads them).
  vk::Buffer meshes;              // SurfaceMeshGpu[]: first global triangle, count, first vertex, material
  vk::Buffer materials;           // SurfaceMaterialGpu[]
  vk::Buffer triangles;           // SurfaceTriangleGpu[], by global triangle index
  vk::Buffer point_lights;        // PointLightGpu[] (one unused entry when there are none)
  vk::Buffer directional_lights;  // DirectionalLightGpu[]
  vk::Buffer emitters;            // EmitterGpu[]: the non-degenerate triangles of emissive materials
  glm::dvec3 origin{0.0};
  double scale = 0.0;             // largest |vertex coordinate - origin| (shadow-ray offsets: SurfaceFrame subpixel.z)
  uint32_t vertex_count = 0;
  uint32_t triangle_count = 0;
  uint32_t point_light_count = 0;
  uint32_t directional_light_count = 0;
  uint32_t emitter_count = 0;
  Sky sky;
  uint64_t bytes = 0;             // GPU memory the buffers hold
};

// The serials of the scene's buffers (vk::Buffer::serial): equal keys, the same buffers.
using SceneBufferKey = std::array<uint64_t, 9>;
SceneBufferKey buffer_key(const GpuSurfaceScene& scene);

// Throws InputError for an invalid scene (validate), radiometric values beyond what float32
// holds with its headroom (validate_float_range), or a triangle count that does not fit the
// device's storage-buffer range.
GpuSurfaceScene upload(const vk::Device& device, const SurfaceScene& scene);

}  // namespace prismoid::surface
