#include "app/bench/mixed_bench.hpp"

#include <chrono>
#include <iostream>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "app/common/backend_cache.hpp"
#include "app/common/cli_args.hpp"
#include "renderer/metrics/flip.hpp"
#include "renderer/metrics/image_error.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/surface_scene.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::bench {

SurfaceScene cutting_square(const Bounds& bounds, const Camera& camera) {
  const glm::dvec3 forward = glm::normalize(camera.target - camera.eye);
  const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
  const glm::dvec3 up = glm::cross(right, forward);
  const glm::dvec3 c = bounds.center();
  const double a = 0.5 * bounds.radius();
  SceneMesh square;
  square.name = "cutting square";
  // Counter-clockwise seen from the camera: the normal faces it.
  square.positions = {c - a * right - a * up, c + a * right - a * up, c + a * right + a * up, c - a * right + a * up};
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  SurfaceScene scene;
  scene.name = "cutting square";
  scene.materials.push_back({});
  scene.meshes.push_back(std::move(square));
  return with_default_lighting(std::move(scene), camera);
}

std::vector<BenchRow> bench_mixed(const vk::Device& device, const app::VolumeChoice& volume, const Camera& camera,
                                  const MixedBenchOptions& options) {
  const SurfaceScene surfaces = cutting_square(bounds_of(volume.mesh), camera);
  const VkExtent2D extent{options.width, options.height};
  std::optional<mixed::SceneFrame> reference;  // the same for every row: the surfaces' direct light, without shadows
  double reference_ms = 0.0;
  std::vector<BenchRow> rows;
  // One renderer: the mesh and the surfaces are uploaded once, each backend and mode made on first use.
  mixed::SceneRenderer renderer({.volume = &volume.mesh, .surfaces = &surfaces}, device, app::resolve_auto_backend);
  for (const volume::VolumeBackendInfo* backend : volume::volume_backend_table()) {
    if (!backend->gpu() || !volume::device_problem(*backend, device.capabilities()).empty()) continue;
    for (const surface::SurfaceMode& mode : surface::surface_mode_table()) {
      if (!mode.gpu() || mode.gi != frame::SurfaceGi::None || !mode.backend->device_problem(device).empty()) continue;
      mixed::SceneSettings settings;
      settings.size = extent;
      settings.volume_mode = volume.mode;
      settings.volume = volume.settings;
      settings.volume.backend = frame::IntervalBackend{backend->name};
      settings.surface_mode = &mode;
      settings.shadows = false;
      settings.frames = options.frames;
      settings.warm_up_seconds = options.warm_up_seconds;
      const mixed::SceneFrame drawn = renderer.render(camera, settings);
      const mixed::MixedFrame& f = *drawn.mixed;
      if (!reference) {
        const auto start = std::chrono::steady_clock::now();
        reference = renderer.reference(camera, settings, drawn);
        reference_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      }
      const std::vector<float>& ref = reference->mixed->display;
      BenchRow m;
      m.dataset = volume.mesh.name;
      m.cells = volume.mesh.tets.size();
      m.sweep = "mixed";
      m.quantity = app::quantity_name(volume.quantity);
      m.mode = std::string(volume.mode->name) + "+" + std::string(mode.name);
      m.settings = "volume-backend=" + std::string(backend->name);
      m.ordering = f.volume.report.ordering;
      m.width = extent.width;
      m.height = extent.height;
      set_times(m, *drawn.timing);
      m.cpu_ms = vk::total_gpu_ms(f.cpu_passes);
      m.mesh_bytes = f.volume.report.mesh_bytes;
      // The composite as displayed, RGB: the volume over the surfaces.
      m.error = reference::image_error(f.display, ref, 1.0, 4, 3);
      m.ssim = reference::ssim(f.display, ref, extent.width, extent.height, 1.0, 4, 3);
      m.flip = reference::flip(f.display, ref, extent.width, extent.height, 4).mean;
      m.peak = 1.0;
      m.reference_ms = reference_ms;
      std::cout << m.dataset << " mixed " << m.quantity << " " << m.mode << " " << m.settings << " " << m.width << "x" << m.height
                << ": " << app::json_number(m.ms_median) << " ms GPU, RMSE " << app::json_number(m.error.rmse) << std::endl;
      rows.push_back(std::move(m));
    }
  }
  return rows;
}

}  // namespace prismoid::bench
