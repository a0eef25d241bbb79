#include "renderer/frame/frame_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/vk/device.hpp"
#include "renderer/volume/compute/compute_backend.hpp"
#include "renderer/volume/mesh/mesh_backend.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/input_error.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

namespace {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// What the last recorded frame left in device memory, for the planner's reuse decisions.
struct FrameRenderer::Recorded {
  bool any = false;
  glm::dvec3 eye{0.0};
};

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& mesh)
    : FrameRenderer(device, mesh, frame_units(bounds_of(mesh))) {}

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& world, const FrameUnits& units)
    : FrameRenderer(device, world, units, in_units(world, units)) {}

FrameRenderer::FrameRenderer(const vk::Device& device, const TetMesh& world, const FrameUnits& units, const TetMesh& local)
    : device_(device), units_(units), mesh_(volume::upload(device, local)), bounds_(bounds_of(world)),
      float_facts_(volume::float_facts(local)), inputs_(device), resolve_(device), geometry_(std::make_unique<TetMesh>()),
      recorded_(std::make_unique<Recorded>()), offscreen_timer_(device, 16) {
  float_facts_.unit = units_.unit;
  geometry_->name = local.name;
  geometry_->points = local.points;
  geometry_->tets = local.tets;
  point_extinction_ = local.linear_extinction();
  point_scalars_ = !local.point_scalars.empty();
}

bool FrameRenderer::update_fields(const TetMesh& world) {
  // The same conversion as the constructor's: equal world points give equal local points.
  const TetMesh local = in_units(world, units_);
  if (local.tets != geometry_->tets || local.points != geometry_->points) return false;
  validate(local);
  device_.wait_idle();  // no frame may still read the old fields
  volume::upload_fields(device_, mesh_, local);
  float_facts_ = volume::float_facts(local);
  float_facts_.unit = units_.unit;
  geometry_->name = local.name;
  point_extinction_ = local.linear_extinction();
  point_scalars_ = !local.point_scalars.empty();
  return true;
}

volume::GpuVolumeBackend& FrameRenderer::backend_for(const FrameSettings& settings) {
  const std::string name = interval_backend_name(settings.backend);
  const auto found = backends_.find(name);
  if (found != backends_.end()) return *found->second;
  const volume::VolumeBackendInfo* info = volume::find_volume_backend(name);
  if (!info || !info->gpu()) throw std::logic_error("FrameRenderer: no GPU volume backend named " + name);
  return *backends_.emplace(name, info->make({device_, mesh_, *geometry_})).first->second;
}

const volume::GpuVolumeBackend* FrameRenderer::backend(std::string_view name) const {
  const auto found = backends_.find(name);
  return found == backends_.end() ? nullptr : found->second.get();
}

const volume::ComputeIntervals* FrameRenderer::compute_intervals() const {
  const auto* compute = dynamic_cast<const volume::ComputeBackend*>(backend(volume::compute_backend().name));
  return compute ? &compute->intervals() : nullptr;
}

const volume::VisibilitySort* FrameRenderer::gpu_sort() const {
  const auto* mesh = dynamic_cast<const volume::MeshBackend*>(backend(volume::mesh_backend().name));
  return mesh ? mesh->gpu_sort() : nullptr;
}

std::optional<volume::DrawCounts> FrameRenderer::draw_counts() const {
  return recorded_->any && active_ ? active_->draw_counts() : std::nullopt;
}

FrameSettings FrameRenderer::local_settings(const FrameSettings& settings) const {
  FrameSettings local = settings;
  if (settings.resolve.depth_limit && settings.resolve.depth_limit != limit_world_) {
    limit_local_ = limit_in_units(*settings.resolve.depth_limit, units_);
    limit_world_ = settings.resolve.depth_limit;  // kept, so its address names this limit
  }
  local.resolve = in_units(settings.resolve, units_, limit_local_);
  return local;
}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::forget_history() {
  *recorded_ = Recorded{};
  for (auto& [name, backend] : backends_) backend->forget_history();
}

void FrameRenderer::resize(VkExtent2D extent) {
  if (extent.width == targets_.extent.width && extent.height == targets_.extent.height) return;
  device_.wait_idle();
  targets_ = volume::create_targets(device_, extent);
}

SceneContents FrameRenderer::scene_contents(const Camera& camera, const FrameSettings& world_settings) const {
  const FrameSettings settings = local_settings(world_settings);
  SceneContents scene;
  scene.volumes.push_back(volume_contents(mesh_.tet_count, point_extinction_, point_scalars_, settings.resolve));
  const Recorded& last = *recorded_;
  scene.camera_moved = !last.any || camera.eye != last.eye;
  scene.scene_moved = !last.any;  // the mesh and its fields are fixed for the renderer's life
  scene.transfer_changed =
      settings.resolve.quantity == volume::Quantity::Color && !inputs_.transfer_current(mesh_, settings.resolve);
  const auto made = backends_.find(std::string_view(interval_backend_name(settings.backend)));
  if (made != backends_.end()) {
    const volume::BackendHistory history = made->second->history(settings);
    scene.order_kept = history.order_kept;
    scene.tetlets_built = history.tetlets_built;
  }
  return scene;
}

FrameReport FrameRenderer::prepare(const Camera& world_camera, const FrameSettings& world_settings) {
  plan_.reset();
  const Camera camera = in_units(world_camera, units_);
  const FrameSettings settings = local_settings(world_settings);
  FrameReport report;
  for (const vk::Buffer* b : {&mesh_.positions, &mesh_.tets, &mesh_.cell_sigma, &mesh_.point_sigma, &mesh_.cell_scalar, &mesh_.point_scalar})
    report.mesh_bytes += b->size();
  // Rays ending at opaque geometry: every backend clips each interval at the pixel's limit, for
  // the quantities the CPU reference integrates.
  if (const auto& limit = settings.resolve.depth_limit) {
    if (limit->size() != size_t(targets_.extent.width) * targets_.extent.height)
      throw InputError("depth limit", "has " + std::to_string(limit->size()) + " values for a " + std::to_string(targets_.extent.width) +
                                          "x" + std::to_string(targets_.extent.height) + " frame");
    if (settings.resolve.march.enabled || settings.resolve.quantity == volume::Quantity::Isosurface)
      throw InputError("depth limit", "is not followed when marching a field or drawing an isosurface");
  }
  volume::check_workgroup_settings(settings.resolve);
  // What the backend draws, from its line of the table: it is refused by name for the rest.
  const volume::VolumeBackendInfo* info = volume::find_volume_backend(interval_backend_name(settings.backend));
  if (info && settings.resolve.depth_limit && !info->supports.depth_limit)
    throw InputError("depth limit", "the " + std::string(info->name) + " volume backend does not end rays at opaque geometry");
  if (info && (settings.resolve.march.enabled || settings.resolve.quantity == volume::Quantity::Isosurface) && !info->supports.march)
    throw InputError("march", "the " + std::string(info->name) + " volume backend does not sample a field inside its intervals");
  volume::GpuVolumeBackend& backend = backend_for(settings);
  active_ = &backend;
  const volume::BackendPrepare frame{camera, settings, targets_.extent};
  backend.check(frame);
  inputs_.prepare(mesh_, settings.resolve);
  report.warnings =
      volume::check_float_limits(float_facts_, camera, targets_.extent.width, targets_.extent.height, settings.resolve, true,
                                 &geometry_->points)
          .warnings;
  report.plan = plan_frame(scene_contents(world_camera, world_settings), settings);
  report.backend = interval_backend_name(settings.backend);
  for (const PlannedPass& pass : report.plan.passes) {
    if (pass.kind != PassKind::Cpu) continue;
    const auto start = std::chrono::steady_clock::now();
    if (pass.id == PassId::TransferUpload || pass.id == PassId::Preintegrate) inputs_.upload_transfer(mesh_, settings.resolve);
    else if (!backend.run_cpu(pass, frame))
      throw std::logic_error("FrameRenderer: the plan has a CPU pass it cannot run: " + pass.name);
    report.cpu_passes.push_back({pass.name, ms_since(start)});
  }
  backend.prepared(frame, report.plan, report);
  plan_ = report.plan;
  plan_eye_ = world_camera.eye;
  return report;
}

void FrameRenderer::record(VkCommandBuffer cmd, const Camera& world_camera, const FrameSettings& world_settings,
                           vk::GpuTimer& timer) {
  if (!plan_) throw std::logic_error("FrameRenderer: record() needs prepare() first");
  if (world_camera.eye != plan_eye_) throw std::logic_error("FrameRenderer: record() for another eye than prepare() planned for");
  const Camera camera = in_units(world_camera, units_);
  const FrameSettings settings = local_settings(world_settings);
  if (!active_) throw std::logic_error("FrameRenderer: record() without a backend");
  const size_t first_timed = timer.recorded().size();
  const volume::BackendRecord frame{cmd, camera, settings, inputs_, targets_, timer};
  for (const PlannedPass& pass : plan_->passes) {
    if (pass.kind != PassKind::Gpu) continue;
    if (pass.id == PassId::Resolve) resolve_.record(cmd, targets_, settings.resolve, active_->accumulated_by(), timer);
    else if (!active_->record(pass, frame))
      throw std::logic_error("FrameRenderer: the plan has a GPU pass it cannot record: " + pass.name);
  }
  // The plan is the single source of truth: what was timed is exactly what was planned.
  const std::vector<std::string> timed(timer.recorded().begin() + std::ptrdiff_t(first_timed), timer.recorded().end());
  if (timed != plan_->gpu_pass_names()) throw std::logic_error("FrameRenderer: recorded passes differ from the plan");
  recorded_->any = true;
  recorded_->eye = world_camera.eye;
  // What the last frame left is the drawing backend's alone: the others plan as for a first frame.
  for (auto& [name, backend] : backends_)
    if (backend.get() != active_) backend->forget_history();
  active_->recorded(settings);
}

OffscreenFrame FrameRenderer::render_timed(const Camera& camera, const FrameSettings& settings, VkExtent2D extent) {
  resize(extent);
  OffscreenFrame frame;
  for (int attempt = 0;; ++attempt) {
    frame.report = prepare(camera, settings);
    device_.submit_and_wait([&](VkCommandBuffer cmd) {
      offscreen_timer_.reset(cmd);
      record(cmd, camera, settings, offscreen_timer_);
    });
    // A backend that drew only part of its work (the compute backend's pairs past its
    // buffers) draws the frame again, with room for all of it.
    if (active_->finished(local_settings(settings), frame.report)) break;
    if (attempt > 0) throw std::logic_error("FrameRenderer: the " + frame.report.backend + " backend's frame did not fit after growing");
    forget_history();
  }
  frame.width = extent.width;
  frame.height = extent.height;
  frame.passes = offscreen_timer_.read();
  return frame;
}

OffscreenFrame FrameRenderer::render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent) {
  OffscreenFrame frame = render_timed(camera, settings, extent);
  const size_t pixels = size_t(extent.width) * extent.height;
  frame.quantity.resize(pixels);
  frame.display.resize(pixels * 4);
  vk::read_image(device_, targets_.quantity, sizeof(float), std::as_writable_bytes(std::span(frame.quantity)));
  vk::read_image(device_, targets_.display, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.display)));
  if (settings.resolve.quantity == volume::Quantity::Color || settings.resolve.quantity == volume::Quantity::Isosurface) {
    frame.emission.resize(pixels * 4);
    vk::read_image(device_, targets_.emission, 4 * sizeof(float), std::as_writable_bytes(std::span(frame.emission)));
    // An isosurface's hit distance is a length: back to world units.
    if (settings.resolve.quantity == volume::Quantity::Isosurface)
      for (size_t i = 3; i < frame.emission.size(); i += 4) frame.emission[i] = float(double(frame.emission[i]) * units_.unit);
  }
  return frame;
}

}  // namespace prismoid::frame
