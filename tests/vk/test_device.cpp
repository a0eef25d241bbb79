#include <gtest/gtest.h>

#include <cstring>

#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/memory.hpp"
#include "shaders/shared/volume.h"
#include "support/gpu_fixture.hpp"

namespace prismoid {
namespace {

class DeviceTest : public test::GpuTest {};

TEST_F(DeviceTest, ChosenDeviceHasMeshShaders) {
  const auto& caps = device().capabilities();
  EXPECT_TRUE(caps.mesh_shader) << caps.name;
  EXPECT_TRUE(caps.api_1_3);
  EXPECT_NE(caps.queue_family, UINT32_MAX);
  // What the interval-shading mesh shader declares per workgroup.
  EXPECT_GE(caps.max_mesh_output_vertices, uint32_t(PRISMOID_WORKGROUP_MAX_VERTICES));
  EXPECT_GE(caps.max_mesh_output_primitives, uint32_t(PRISMOID_WORKGROUP_MAX_TRIANGLES));
}

TEST_F(DeviceTest, BufferRoundTripsThroughTheGpu) {
  std::vector<uint32_t> data(1000);
  for (uint32_t i = 0; i < data.size(); ++i) data[i] = i * 2654435761u;
  vk::Buffer gpu = vk::upload_buffer(device(), std::as_bytes(std::span(data)), VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  vk::Buffer back(device(), gpu.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::HostVisible);
  device().submit_and_wait([&](VkCommandBuffer cmd) {
    VkBufferCopy region{0, 0, gpu.size()};
    vkCmdCopyBuffer(cmd, gpu.get(), back.get(), 1, &region);
  });
  EXPECT_EQ(std::memcmp(back.mapped(), data.data(), gpu.size()), 0);
}

TEST(DeviceSelection, PrefersDiscreteGpuOverCpu) {
  vk::DeviceCapabilities cpu, gpu;
  cpu.index = 0; cpu.name = "cpu"; cpu.device_type = VK_PHYSICAL_DEVICE_TYPE_CPU;
  gpu.index = 1; gpu.name = "gpu"; gpu.device_type = VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU;
  for (auto* d : {&cpu, &gpu}) { d->api_1_3 = true; d->mesh_shader = true; d->queue_family = 0; }
  std::vector<vk::DeviceCapabilities> devices = {cpu, gpu};
  EXPECT_EQ(vk::select_device(devices, std::nullopt).name, "gpu");
  EXPECT_EQ(vk::select_device(devices, 0u).name, "cpu");
}

TEST(DeviceSelection, RefusesDevicesWithoutMeshShadersWithAReason) {
  vk::DeviceCapabilities old;
  old.name = "old lavapipe"; old.api_1_3 = true; old.queue_family = 0; old.mesh_shader = false;
  std::vector<vk::DeviceCapabilities> devices = {old};
  try {
    vk::select_device(devices, std::nullopt);
    FAIL() << "expected NoSuitableDevice";
  } catch (const vk::NoSuitableDevice& e) {
    EXPECT_NE(std::string(e.what()).find("mesh shaders"), std::string::npos) << e.what();
  }
  EXPECT_THROW(vk::select_device(devices, 7u), vk::NoSuitableDevice);
}

TEST(ModeRequirements, GiNeedsRayTracingPipelinesButNotRayQuery) {
  for (const auto& m : vk::mode_requirements()) {
    if (m.mode.find("GI") == std::string::npos) continue;
    auto has = [&](vk::Feature f) { return std::find(m.required.begin(), m.required.end(), f) != m.required.end(); };
    EXPECT_TRUE(has(vk::Feature::RayTracingPipeline));
    EXPECT_FALSE(has(vk::Feature::RayQuery));
    return;
  }
  FAIL() << "no GI row in the mode table";
}

}  // namespace
}  // namespace prismoid
