// Build times of acceleration structures (not a test: nothing is asserted). Prints, for the
// Cornell box and a generated ~1M-triangle height field, the host wall-clock time of each
// build stage and the structures' sizes, over a few repetitions, validation off.
//   rt_build_timing [repetitions]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "renderer/rt/acceleration_structure.hpp"
#include "renderer/rt/ray_caster.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"
#include "scene/surface_generators.hpp"

namespace {

using namespace prismoid;

// An n x n grid of points over [0, 1000]^2 with a wavy height: 2 (n - 1)^2 triangles.
SurfaceScene height_field(uint32_t n) {
  SurfaceScene s;
  s.name = "height field";
  s.materials = {default_surface_material()};
  SceneMesh mesh;
  mesh.name = "height field";
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const double x = 1000.0 * i / (n - 1), z = 1000.0 * j / (n - 1);
      mesh.positions.push_back({x, 40.0 * std::sin(x * 0.05) * std::cos(z * 0.031), z});
    }
  for (uint32_t j = 0; j + 1 < n; ++j)
    for (uint32_t i = 0; i + 1 < n; ++i) {
      const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      mesh.triangles.push_back({a, c, b});
      mesh.triangles.push_back({b, c, d});
    }
  s.meshes.push_back(std::move(mesh));
  s.camera.eye = {500.0, 600.0, -400.0};
  s.camera.target = {500.0, 0.0, 500.0};
  return s;
}

void report(const vk::Device& device, const SurfaceScene& scene, int repetitions) {
  for (int r = 0; r < repetitions; ++r) {
    const auto start = std::chrono::steady_clock::now();
    const rt::SceneAccel accel(device, scene);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const rt::AccelBuildStats& s = accel.stats();
    std::printf("%-14s %9llu tris  upload %8.2f ms  BLAS %9.2f ms  compact %8.2f ms  TLAS %7.2f ms  total %9.2f ms  "
                "BLAS %7.2f MiB (built %7.2f)  TLAS %.1f KiB  scratch %.1f KiB\n",
                scene.name.c_str(), static_cast<unsigned long long>(s.triangles), 1e3 * s.upload_seconds, 1e3 * s.blas_seconds,
                1e3 * s.compact_seconds, 1e3 * s.tlas_seconds, 1e3 * total, double(s.blas_bytes) / (1 << 20),
                double(s.blas_bytes_built) / (1 << 20), double(s.tlas_bytes) / 1024, double(s.scratch_bytes) / 1024);
    if (r == repetitions - 1) {
      const rt::RayCaster caster(device, accel);
      const auto t0 = std::chrono::steady_clock::now();
      const auto hits = caster.primary_hits(scene.camera, 512, 512);
      const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      size_t hit = 0;
      for (const auto& h : hits) hit += h.hit;
      std::printf("%-14s 512x512 primary rays: %.1f ms including readback (%zu hits)\n", scene.name.c_str(), ms, hit);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  vk::Instance instance(vk::InstanceOptions{});
  const auto devices = vk::query_devices(instance.get());
  const vk::Device device(instance, vk::select_device(devices, std::nullopt), vk::DeviceOptions{});
  std::printf("device: %s (%s)\n", device.capabilities().name.c_str(), device.capabilities().driver_info.c_str());
  if (!device.ray_tracing_enabled()) {
    std::printf("no ray tracing on this device\n");
    return 1;
  }
  report(device, make_cornell_box(), repetitions);
  report(device, height_field(708), repetitions);  // 2 * 707^2 = 999,698 triangles
  return 0;
}
