#include "renderer/rt/acceleration_structure.hpp"

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"

namespace prismoid::rt {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

VkDeviceSize align_up(VkDeviceSize value, VkDeviceSize alignment) {
  return alignment > 1 ? (value + alignment - 1) / alignment * alignment : value;
}

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The rule TriangleBvh skips triangles by: a non-finite corner or a zero (or non-finite) normal.
bool degenerate(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  return !finite(a) || !finite(b) || !finite(c) || !finite(n) || glm::length(n) == 0.0;
}

// A device-local buffer with a device address and room for `bytes` at an address aligned to
// `alignment` (allocations need not be aligned as strictly as scratch memory must be).
struct AlignedBuffer {
  vk::Buffer buffer;
  VkDeviceAddress address = 0;
};
AlignedBuffer aligned_buffer(const vk::Device& device, VkDeviceSize bytes, VkDeviceSize alignment, VkBufferUsageFlags usage) {
  AlignedBuffer b;
  b.buffer = vk::Buffer(device, bytes + alignment, usage | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, vk::MemoryUse::DeviceLocal);
  b.address = align_up(b.buffer.device_address(), alignment);
  return b;
}

constexpr VkBufferUsageFlags kGeometryUsage = VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
                                              VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

}  // namespace

void destroy_acceleration_structure(VkDevice device, VkAccelerationStructureKHR handle, const VkAllocationCallbacks* allocator) {
  const auto destroy = reinterpret_cast<PFN_vkDestroyAccelerationStructureKHR>(
      vkGetDeviceProcAddr(device, "vkDestroyAccelerationStructureKHR"));
  if (destroy) destroy(device, handle, allocator);
}

AccelerationStructure::AccelerationStructure(const vk::Device& device, VkAccelerationStructureTypeKHR type, VkDeviceSize size)
    : storage_(device, size,
               VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
               vk::MemoryUse::DeviceLocal) {
  VkAccelerationStructureCreateInfoKHR info{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  info.buffer = storage_.get();
  info.size = size;
  info.type = type;
  VkAccelerationStructureKHR handle;
  vk::check(device.create_acceleration_structure(device.get(), &info, nullptr, &handle), "vkCreateAccelerationStructureKHR");
  handle_ = UniqueAccelerationStructure(device.get(), handle);
  VkAccelerationStructureDeviceAddressInfoKHR address{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  address.accelerationStructure = handle;
  address_ = device.get_acceleration_structure_device_address(device.get(), &address);
}

glm::vec3 SceneAccel::to_local(const glm::dvec3& p) const { return glm::vec3(p - origin_); }

SceneAccel::SceneAccel(const vk::Device& device, const SurfaceScene& scene, const AccelBuildOptions& options) {
  if (!device.ray_tracing_enabled())
    throw vk::NoSuitableDevice(device.capabilities().name +
                               " has no ray tracing enabled (needs VK_KHR_ray_tracing_pipeline, "
                               "VK_KHR_acceleration_structure and bufferDeviceAddress)");
  validate(scene);
  origin_ = options.origin.value_or(bounds_of(scene).center());
  if (!finite(origin_)) throw InputError(scene.name, "the ray-tracing origin is not finite");
  if (scene.meshes.size() > (1u << 24))
    throw InputError(scene.name, "more than 2^24 meshes (an instance's custom index has 24 bits)");
  const VkDevice dev = device.get();

  // Geometry: local float positions (vec4) and indices per mesh, all uploaded in one submission.
  auto start = Clock::now();
  meshes_.resize(scene.meshes.size());
  std::vector<std::vector<glm::vec4>> positions(scene.meshes.size());
  std::vector<std::vector<uint32_t>> indices(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const SceneMesh& mesh = scene.meshes[m];
    if (mesh.triangles.size() > std::numeric_limits<uint32_t>::max() / 3)
      throw InputError(scene.name, "mesh '" + mesh.name + "' has too many triangles for 32-bit indices");
    positions[m].reserve(mesh.positions.size());
    for (const auto& p : mesh.positions) positions[m].push_back(glm::vec4(to_local(p), 1.0f));
    indices[m].reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) {
      if (degenerate(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]])) {
        indices[m].insert(indices[m].end(), {t[0], t[0], t[0]});  // a point: zero area in any precision
        ++stats_.degenerate_triangles;
      } else {
        indices[m].insert(indices[m].end(), {t[0], t[1], t[2]});
        ++meshes_[m].active;
      }
    }
    meshes_[m].triangles = static_cast<uint32_t>(mesh.triangles.size());
    stats_.triangles += mesh.triangles.size();
    meshes_[m].positions = vk::Buffer(device, positions[m].size() * sizeof(glm::vec4), kGeometryUsage | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      vk::MemoryUse::DeviceLocal);
    meshes_[m].indices = vk::Buffer(device, indices[m].size() * sizeof(uint32_t), kGeometryUsage | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                    vk::MemoryUse::DeviceLocal);
  }
  {
    VkDeviceSize staging_bytes = 0;
    for (size_t m = 0; m < meshes_.size(); ++m)
      staging_bytes += positions[m].size() * sizeof(glm::vec4) + indices[m].size() * sizeof(uint32_t);
    if (staging_bytes > 0) {
      vk::Buffer staging(device, staging_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::HostVisible);
      std::vector<std::pair<VkBufferCopy, VkBuffer>> copies;
      VkDeviceSize at = 0;
      auto stage = [&](const void* data, VkDeviceSize bytes, VkBuffer dst) {
        if (bytes == 0) return;
        std::memcpy(staging.mapped() + at, data, bytes);
        copies.push_back({VkBufferCopy{at, 0, bytes}, dst});
        at += bytes;
      };
      for (size_t m = 0; m < meshes_.size(); ++m) {
        stage(positions[m].data(), positions[m].size() * sizeof(glm::vec4), meshes_[m].positions.get());
        stage(indices[m].data(), indices[m].size() * sizeof(uint32_t), meshes_[m].indices.get());
      }
      device.submit_and_wait([&](VkCommandBuffer cmd) {
        for (const auto& [region, dst] : copies) vkCmdCopyBuffer(cmd, staging.get(), dst, 1, &region);
        vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR | VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                       VK_ACCESS_2_MEMORY_READ_BIT);
      });
    }
  }
  stats_.upload_seconds = seconds_since(start);

  // Bottom level: one structure per mesh with triangles, all built in one submission.
  start = Clock::now();
  const VkDeviceSize scratch_alignment = std::max<VkDeviceSize>(device.capabilities().min_acceleration_structure_scratch_alignment, 1);
  std::vector<size_t> built;  // mesh index per build
  std::vector<VkAccelerationStructureGeometryKHR> geometries;
  std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos;
  std::vector<VkAccelerationStructureBuildRangeInfoKHR> ranges;
  std::vector<VkDeviceSize> scratch_offsets;
  VkDeviceSize scratch_total = 0;
  // A mesh whose triangles are all degenerate gets no structure.
  for (size_t m = 0; m < meshes_.size(); ++m)
    if (meshes_[m].active > 0) built.push_back(m);
  geometries.resize(built.size());
  infos.resize(built.size());
  ranges.resize(built.size());
  for (size_t i = 0; i < built.size(); ++i) {
    Mesh& mesh = meshes_[built[i]];
    VkAccelerationStructureGeometryKHR& g = geometries[i];
    g = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
    g.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
    g.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
    g.geometry.triangles = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR};
    g.geometry.triangles.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
    g.geometry.triangles.vertexData.deviceAddress = mesh.positions.device_address();
    g.geometry.triangles.vertexStride = sizeof(glm::vec4);
    g.geometry.triangles.maxVertex = static_cast<uint32_t>(positions[built[i]].size() - 1);
    g.geometry.triangles.indexType = VK_INDEX_TYPE_UINT32;
    g.geometry.triangles.indexData.deviceAddress = mesh.indices.device_address();
    VkAccelerationStructureBuildGeometryInfoKHR& info = infos[i];
    info = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR |
                 (options.compact ? VK_BUILD_ACCELERATION_STRUCTURE_ALLOW_COMPACTION_BIT_KHR : 0);
    info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    info.geometryCount = 1;
    info.pGeometries = &g;
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    device.get_acceleration_structure_build_sizes(dev, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &mesh.triangles, &sizes);
    mesh.blas = AccelerationStructure(device, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, sizes.accelerationStructureSize);
    info.dstAccelerationStructure = mesh.blas.get();
    scratch_offsets.push_back(scratch_total);
    scratch_total += align_up(sizes.buildScratchSize, scratch_alignment);
    ranges[i] = {mesh.triangles, 0, 0, 0};
    stats_.blas_bytes_built += mesh.blas.size();
  }
  stats_.scratch_bytes = scratch_total;
  vk::UniqueQueryPool sizes_pool;
  if (!built.empty()) {
    AlignedBuffer scratch = aligned_buffer(device, scratch_total, scratch_alignment, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
    std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> range_pointers;
    for (size_t i = 0; i < built.size(); ++i) {
      infos[i].scratchData.deviceAddress = scratch.address + scratch_offsets[i];
      range_pointers.push_back(&ranges[i]);
    }
    std::vector<VkAccelerationStructureKHR> handles;
    for (size_t m : built) handles.push_back(meshes_[m].blas.get());
    if (options.compact) {
      VkQueryPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
      pool_info.queryType = VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR;
      pool_info.queryCount = static_cast<uint32_t>(built.size());
      VkQueryPool pool;
      vk::check(vkCreateQueryPool(dev, &pool_info, nullptr, &pool), "vkCreateQueryPool (compacted sizes)");
      sizes_pool = vk::UniqueQueryPool(dev, pool);
    }
    device.submit_and_wait([&](VkCommandBuffer cmd) {
      device.cmd_build_acceleration_structures(cmd, static_cast<uint32_t>(infos.size()), infos.data(), range_pointers.data());
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                     VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR,
                     VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
      if (sizes_pool) {
        vkCmdResetQueryPool(cmd, sizes_pool.get(), 0, static_cast<uint32_t>(handles.size()));
        device.cmd_write_acceleration_structures_properties(cmd, static_cast<uint32_t>(handles.size()), handles.data(),
                                                            VK_QUERY_TYPE_ACCELERATION_STRUCTURE_COMPACTED_SIZE_KHR,
                                                            sizes_pool.get(), 0);
      }
    });
  }
  stats_.blas_seconds = seconds_since(start);

  // Compaction: copy each BLAS into a structure of the size the build reported.
  start = Clock::now();
  if (sizes_pool) {
    std::vector<VkDeviceSize> compacted(built.size());
    vk::check(vkGetQueryPoolResults(dev, sizes_pool.get(), 0, static_cast<uint32_t>(built.size()),
                                    compacted.size() * sizeof(VkDeviceSize), compacted.data(), sizeof(VkDeviceSize),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
              "vkGetQueryPoolResults (compacted sizes)");
    std::vector<AccelerationStructure> copies;
    for (size_t i = 0; i < built.size(); ++i)
      copies.emplace_back(device, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, compacted[i]);
    device.submit_and_wait([&](VkCommandBuffer cmd) {
      for (size_t i = 0; i < built.size(); ++i) {
        VkCopyAccelerationStructureInfoKHR copy{VK_STRUCTURE_TYPE_COPY_ACCELERATION_STRUCTURE_INFO_KHR};
        copy.src = meshes_[built[i]].blas.get();
        copy.dst = copies[i].get();
        copy.mode = VK_COPY_ACCELERATION_STRUCTURE_MODE_COMPACT_KHR;
        device.cmd_copy_acceleration_structure(cmd, &copy);
      }
      // Copies run in the build stage (the copy stage needs VK_KHR_ray_tracing_maintenance1).
      vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                     VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    });
    for (size_t i = 0; i < built.size(); ++i) meshes_[built[i]].blas = std::move(copies[i]);
  }
  for (size_t m : built) stats_.blas_bytes += meshes_[m].blas.size();
  stats_.compact_seconds = seconds_since(start);

  // Top level: one instance per BLAS, identity transform (positions are already local).
  start = Clock::now();
  std::vector<VkAccelerationStructureInstanceKHR> instances;
  for (size_t m : built) {
    VkAccelerationStructureInstanceKHR inst{};
    inst.transform.matrix[0][0] = inst.transform.matrix[1][1] = inst.transform.matrix[2][2] = 1.0f;
    inst.instanceCustomIndex = static_cast<uint32_t>(m) & 0xFFFFFFu;
    inst.mask = 0xFFu;
    inst.instanceShaderBindingTableRecordOffset = 0;
    inst.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR & 0xFFu;
    inst.accelerationStructureReference = meshes_[m].blas.address();
    instances.push_back(inst);
  }
  instance_count_ = static_cast<uint32_t>(instances.size());
  // At least one record so the instance address is always a real buffer's (16-byte aligned).
  instances_ = vk::Buffer(device, std::max<size_t>(instances.size(), 1) * sizeof(VkAccelerationStructureInstanceKHR),
                          VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                          vk::MemoryUse::HostVisible);
  if (!instances.empty()) instances_.write(std::as_bytes(std::span(instances)));
  VkAccelerationStructureGeometryKHR tg{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  tg.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  tg.flags = VK_GEOMETRY_OPAQUE_BIT_KHR;
  tg.geometry.instances = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR};
  tg.geometry.instances.arrayOfPointers = VK_FALSE;
  tg.geometry.instances.data.deviceAddress = instances_.device_address();
  VkAccelerationStructureBuildGeometryInfoKHR tinfo{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  tinfo.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  tinfo.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  tinfo.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  tinfo.geometryCount = 1;
  tinfo.pGeometries = &tg;
  VkAccelerationStructureBuildSizesInfoKHR tsizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  device.get_acceleration_structure_build_sizes(dev, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &tinfo, &instance_count_, &tsizes);
  tlas_ = AccelerationStructure(device, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, tsizes.accelerationStructureSize);
  stats_.tlas_bytes = tlas_.size();
  stats_.scratch_bytes = std::max(stats_.scratch_bytes, tsizes.buildScratchSize);
  AlignedBuffer scratch = aligned_buffer(device, tsizes.buildScratchSize, scratch_alignment, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT);
  tinfo.dstAccelerationStructure = tlas_.get();
  tinfo.scratchData.deviceAddress = scratch.address;
  const VkAccelerationStructureBuildRangeInfoKHR trange{instance_count_, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* trange_pointer = &trange;
  device.submit_and_wait([&](VkCommandBuffer cmd) {
    device.cmd_build_acceleration_structures(cmd, 1, &tinfo, &trange_pointer);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                   VK_PIPELINE_STAGE_2_RAY_TRACING_SHADER_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
  });
  stats_.tlas_seconds = seconds_since(start);
}

void write_tlas_descriptor(const vk::Device& device, VkDescriptorSet set, uint32_t binding, VkAccelerationStructureKHR tlas) {
  VkWriteDescriptorSetAccelerationStructureKHR as{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
  as.accelerationStructureCount = 1;
  as.pAccelerationStructures = &tlas;
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.pNext = &as;
  write.dstSet = set;
  write.dstBinding = binding;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
  vkUpdateDescriptorSets(device.get(), 1, &write, 0, nullptr);
}

}  // namespace prismoid::rt
