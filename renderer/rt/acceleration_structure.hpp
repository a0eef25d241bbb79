#pragma once
// Acceleration structures of a SurfaceScene for ray-tracing pipelines: one bottom-level
// structure (BLAS) of opaque triangles per mesh and one top-level structure (TLAS) with an
// instance of each, built on the device with scratch buffers, the BLASes optionally compacted.
//
// Precision: positions go to the GPU as floats relative to a per-scene origin (by default the
// centre of the scene's bounds). Each position is taken minus the origin in double on the CPU
// and only then rounded, so a scene far from the world origin (say at 1e6) keeps the float
// precision of one at the origin: its rounding error is u |p - origin| (u = 2^-24) instead of
// u |p|. Everything traced against these structures (ray origins, lights, points) must be given
// in the same origin-relative frame; SceneAccel::to_local does that subtraction.
//
// Identifiers: instance i of the TLAS has custom index = its mesh's index in the scene, and the
// primitive index within a BLAS is the triangle's index within its mesh, so a hit names
// (gl_InstanceCustomIndexEXT, gl_PrimitiveID) = (mesh, triangle) as the scene does.
//
// Degenerate triangles (zero area or a non-finite corner, in double: the rule the CPU reference
// TriangleBvh skips by) keep their slot, so the indices above still hold, but all three of their
// indices are set to their first corner's: a point, of zero area in float as in double, which a
// ray-triangle test (det == 0) never hits. A mesh with no other triangles gets no BLAS and no
// instance (as a mesh without triangles). Not used: the specification's "inactive" triangles (a
// vertex with a NaN x), since lavapipe (Mesa 25) then loses real triangles sharing BVH nodes
// with them, seen here as missing hits.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>
#include <vulkan/vulkan.h>

#include "renderer/vk/handle.hpp"
#include "renderer/vk/memory.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::vk {
class Device;
}

namespace prismoid::rt {

// vkDestroyAccelerationStructureKHR, looked up through vkGetDeviceProcAddr (the loader does not
// export extension commands), in the shape DeviceHandle wants.
void destroy_acceleration_structure(VkDevice device, VkAccelerationStructureKHR handle, const VkAllocationCallbacks* allocator);
using UniqueAccelerationStructure = vk::DeviceHandle<VkAccelerationStructureKHR, destroy_acceleration_structure>;

// One acceleration structure with the buffer it lives in.
class AccelerationStructure {
 public:
  AccelerationStructure() = default;
  // An empty structure of `type` with room for `size` bytes.
  AccelerationStructure(const vk::Device& device, VkAccelerationStructureTypeKHR type, VkDeviceSize size);
  VkAccelerationStructureKHR get() const { return handle_.get(); }
  uint64_t serial() const { return storage_.serial(); }  // its storage's (vk::Buffer::serial)
  VkDeviceAddress address() const { return address_; }
  VkDeviceSize size() const { return storage_.size(); }

 private:
  vk::Buffer storage_;  // declared first: the structure is destroyed before its storage
  UniqueAccelerationStructure handle_;
  VkDeviceAddress address_ = 0;
};

struct AccelBuildOptions {
  std::optional<glm::dvec3> origin;  // default: the centre of the scene's bounds
  bool compact = true;               // copy each BLAS into a structure of its compacted size
};

// What building took; times are host wall-clock seconds around each submission (report them,
// never assert them).
struct AccelBuildStats {
  double upload_seconds = 0.0;  // vertex and index buffers to the device
  double blas_seconds = 0.0;    // all BLAS builds (one submission)
  double compact_seconds = 0.0; // compacted-size query readback, allocation and copies
  double tlas_seconds = 0.0;    // instance upload and the TLAS build
  uint64_t triangles = 0;
  uint64_t degenerate_triangles = 0;      // degenerate triangles, turned into points (see above)
  VkDeviceSize blas_bytes = 0;          // BLAS storage after compaction (if any)
  VkDeviceSize blas_bytes_built = 0;    // BLAS storage as built, before compaction
  VkDeviceSize tlas_bytes = 0;
  VkDeviceSize scratch_bytes = 0;       // the larger of the BLAS and TLAS scratch buffers
};

// Writes `tlas` to an acceleration-structure binding of a descriptor set.
void write_tlas_descriptor(const vk::Device& device, VkDescriptorSet set, uint32_t binding, VkAccelerationStructureKHR tlas);

class SceneAccel {
 public:
  // Throws InputError for an invalid scene (validate), vk::NoSuitableDevice when the device has
  // no ray tracing enabled (Device::ray_tracing_enabled).
  SceneAccel(const vk::Device& device, const SurfaceScene& scene, const AccelBuildOptions& options = {});

  const glm::dvec3& origin() const { return origin_; }
  // p - origin() in double, rounded to float: the frame every GPU-side coordinate is in.
  glm::vec3 to_local(const glm::dvec3& p) const;
  VkAccelerationStructureKHR tlas() const { return tlas_.get(); }
  uint64_t tlas_serial() const { return tlas_.serial(); }
  uint32_t instance_count() const { return instance_count_; }
  size_t mesh_count() const { return meshes_.size(); }
  // Per mesh: positions as vec4 (xyz relative to origin(), w = 1) and three uint32 indices per
  // triangle (a degenerate triangle's are its first corner's, three times); usable as storage
  // buffers and by device address. Empty stub buffers for a mesh without triangles.
  const vk::Buffer& positions(size_t mesh) const { return meshes_.at(mesh).positions; }
  const vk::Buffer& indices(size_t mesh) const { return meshes_.at(mesh).indices; }
  const AccelBuildStats& stats() const { return stats_; }

 private:
  struct Mesh {
    vk::Buffer positions, indices;
    AccelerationStructure blas;  // none for a mesh without active (non-degenerate) triangles
    uint32_t triangles = 0;
    uint32_t active = 0;
  };
  glm::dvec3 origin_{0.0};
  std::vector<Mesh> meshes_;
  vk::Buffer instances_;
  AccelerationStructure tlas_;
  uint32_t instance_count_ = 0;
  AccelBuildStats stats_;
};

}  // namespace prismoid::rt
