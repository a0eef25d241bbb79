#include "renderer/mixed/scene_renderer.hpp"

#include <stdexcept>
#include <utility>

#include "renderer/mixed/mixed_reference.hpp"
#include "renderer/timing/warm_up.hpp"
#include "renderer/surface/surface_backend.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/volume/float_limits.hpp"
#include "renderer/volume/volume_backends.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::mixed {

namespace {

const char* const kVolumeReference = "CPU reference (double precision)";

// Refuses shadows asked of a device that traces no rays.
void set_shadows(surface::SurfaceRenderer& renderer, const std::optional<bool>& shadows, const std::string& device) {
  if (!shadows) return;
  if (*shadows && !renderer.can_shadow())
    throw vk::NoSuitableDevice(device + " has no ray tracing (VK_KHR_ray_tracing_pipeline and VK_KHR_acceleration_structure): "
                               "shadows need it; use " + setting("shadows", "off"));
  renderer.set_shadows(*shadows);
}

// `frames` timed calls of `frame` (each returning its passes), after the warm-up SceneSettings says.
timing::FrameTiming timed(const SceneSettings& settings, const std::function<std::vector<vk::PassTiming>()>& frame) {
  const std::optional<double> warm_up =
      settings.warm_up_seconds ? settings.warm_up_seconds
                               : settings.frames > 1 ? std::optional<double>(timing::kTimedWarmUpSeconds) : std::nullopt;
  if (warm_up) timing::warm_up([&] { return vk::total_gpu_ms(frame()); }, *warm_up);
  return timing::time_frames(settings.frames, frame);
}

}  // namespace

SceneRenderer::SceneRenderer(SceneData scene, DeviceRequest device, AutoBackend auto_backend)
    : scene_(scene), request_(device), auto_backend_(std::move(auto_backend)) {
  if (!scene_.volume && !scene_.surfaces) throw std::invalid_argument("SceneRenderer: a scene of neither a volume nor surfaces");
}

SceneRenderer::SceneRenderer(SceneData scene, const vk::Device& device, AutoBackend auto_backend)
    : SceneRenderer(scene, DeviceRequest{}, std::move(auto_backend)) {
  device_ = &device;
  device_name_ = device.capabilities().name;
  driver_ = device.capabilities().driver_info;
}

SceneRenderer::~SceneRenderer() = default;

const vk::Device& SceneRenderer::device() {
  if (!device_) {
    instance_ = std::make_unique<vk::Instance>(vk::InstanceOptions{.validation = request_.validation});
    const auto devices = vk::query_devices(instance_->get());
    const vk::DeviceCapabilities& caps = vk::select_device(devices, request_.index);
    device_name_ = caps.name;
    driver_ = caps.driver_info;
    owned_device_ = std::make_unique<vk::Device>(*instance_, caps, vk::DeviceOptions{});
    device_ = owned_device_.get();
  }
  return *device_;
}

void SceneRenderer::gpu_identity(SceneFrame& f) const {
  f.gpu = true;
  f.device = device_name_;
  f.driver = driver_;
}

void SceneRenderer::resolve_auto(frame::FrameSettings& volume, const SceneSettings& settings, const vk::Device& device) const {
  if (!settings.volume_backend_auto) return;
  // Never drawn on the default backend while the caller believes it asked for the fastest.
  if (!auto_backend_) throw std::invalid_argument("SceneRenderer: an automatic volume backend, and no AutoBackend to choose it");
  auto_backend_(volume, device);
}

SceneFrame SceneRenderer::render(const Camera& camera, const SceneSettings& settings) {
  if (!settings.interactive && settings.frames == 0) throw InputError(setting("frames"), "at least one timed frame");
  SceneFrame f = scene_.volume && scene_.surfaces ? render_mixed(camera, settings)
                 : scene_.volume                  ? render_volume(camera, settings)
                                                  : render_surfaces(camera, settings);
  fill_stats(f, settings);
  return f;
}

void SceneRenderer::fill_stats(SceneFrame& f, const SceneSettings& settings) const {
  FrameStats& s = f.stats;
  s.device = f.device;
  s.driver = f.driver;
  s.gpu = f.gpu;
  s.width = settings.size.width;
  s.height = settings.size.height;
  s.frames = settings.interactive ? 1 : settings.frames;
  s.timing = f.timing;
  const auto volume_stats = [&](const frame::FrameReport& report) {
    return VolumeStats{.dataset = scene_.volume->name,
                       .cells = scene_.volume->tets.size(),
                       .mode = std::string(settings.volume_mode->name),
                       .settings = f.volume_settings,
                       .report = report,
                       .analytic_field = scene_.analytic_field};
  };
  if (f.volume) {
    s.volume = volume_stats(f.volume->report);
    s.passes = f.volume->passes;
    s.cpu_passes = f.volume->report.cpu_passes;
    s.plan = f.volume->report.plan;
    s.warnings = f.volume->report.warnings;
  } else if (f.mixed) {
    s.volume = volume_stats(f.mixed->volume.report);
    size_t triangles = 0;
    for (const SceneMesh& m : scene_.surfaces->meshes) triangles += m.triangles.size();
    s.mixed = MixedSurfaceStats{.scene = scene_.surfaces->name, .triangles = triangles, .mode = f.mixed->surface_mode, .shadows = f.mixed->shadows};
    s.passes = f.mixed->passes;
    s.cpu_passes = f.mixed->cpu_passes;
    s.mixed_plan = f.mixed->plan;
    s.warnings = f.mixed->volume.report.warnings;
  } else if (f.path) {
    reference::PathTracerSettings path = settings.path;
    path.width = settings.size.width;
    path.height = settings.size.height;
    s.path = PathStats{.scene = scene_.surfaces->name,
                       .mode = std::string(settings.surface_mode->name),
                       .settings = path,
                       .counts = f.path->counts,
                       .seconds = f.path->seconds,
                       .default_lighting = scene_.default_lighting};
  } else if (f.surfaces) {
    const surface::SurfaceRenderer::Offscreen& image = *f.surfaces;
    const surface::GpuSurfaceScene& gpu = surfaces_->gpu_scene();
    const surface::SurfaceBackendInfo& backend = *settings.surface_mode->backend;
    const auto takes = [&](std::string_view option) {
      for (const surface::SurfaceOption& o : backend.options)
        if (o.name == option) return true;
      return false;
    };
    SurfaceStats surfaces{.scene = scene_.surfaces->name,
                          .mode = std::string(settings.surface_mode->name),
                          .triangles = gpu.triangle_count,
                          .emitters = gpu.emitter_count,
                          .gpu_scene_bytes = gpu.bytes,
                          .shadows = image.plan.find(frame::PassId::ShadowRays) != nullptr,
                          .default_lighting = scene_.default_lighting,
                          .supersample = settings.supersample,
                          .takes_supersample = takes("supersample"),
                          .takes_frames = takes("frames"),
                          .counts = image.counts,
                          .gi_frames = surfaces_->gi_frames()};
    for (size_t i = 3; i < image.rgba.size(); i += 4) surfaces.covered_pixels += image.rgba[i] == 1.0f;
    s.surfaces = std::move(surfaces);
    s.passes = image.passes;
    s.plan = image.plan;
  }
}

void SceneRenderer::set_volume(const TetMesh& volume) {
  if (!scene_.volume) throw std::logic_error("SceneRenderer::set_volume: the scene has no volume to replace");
  scene_.volume = &volume;
  try {
    if (volume_ && !volume_->update_fields(volume)) volume_.reset();
    else if (volume_) ++uploads_.fields;
    if (mixed_ && !mixed_->volume_renderer().update_fields(volume)) mixed_.reset();
    else if (mixed_) ++uploads_.fields;
  } catch (...) {
    // A step refused (its fields invalid): no renderer may keep drawing the step before under
    // this one's name; the next frame uploads the step whole and refuses it there too.
    volume_.reset();
    mixed_.reset();
    throw;
  }
}

SceneFrame SceneRenderer::render_volume(const Camera& camera, const SceneSettings& settings) {
  if (!settings.volume_mode) throw std::invalid_argument("SceneRenderer: a volume frame without a volume mode");
  const TetMesh& mesh = *scene_.volume;
  SceneFrame f;
  f.volume_settings = settings.volume;
  if (!settings.volume_mode->gpu()) {
    f.device = kVolumeReference;
    // Double arithmetic, but the image is float32: refused where it cannot hold the answer.
    const volume::FloatCheck check = volume::check_float_limits(volume::float_facts(mesh), camera, settings.size.width,
                                                                settings.size.height, settings.volume.resolve, false);
    f.volume = volume::reference_backend().render(mesh, camera, settings.volume.resolve, settings.size, scene_.analytic_field);
    f.volume->report.warnings = check.warnings;
    return f;
  }
  const vk::Device& gpu = device();
  gpu_identity(f);
  resolve_auto(f.volume_settings, settings, gpu);
  if (!volume_) {
    volume_ = std::make_unique<frame::FrameRenderer>(gpu, mesh);
    ++uploads_.meshes;
  }
  if (settings.interactive) {
    f.volume = volume_->render_offscreen(camera, f.volume_settings, settings.size);
    return f;
  }
  // Timed frames read no image back, so the GPU stays busy (and at its clock) between them; the
  // image comes from one more frame of the same camera.
  std::vector<double> cpu_ms;  // every frame's, the warm-up's first
  f.timing = timed(settings, [&] {
    volume_->forget_history();  // each timed frame costs what a moving camera's does: no order reused
    const frame::OffscreenFrame timed_frame = volume_->render_timed(camera, f.volume_settings, settings.size);
    cpu_ms.push_back(vk::total_gpu_ms(timed_frame.report.cpu_passes));
    return timed_frame.passes;
  });
  f.frame_cpu_ms.assign(cpu_ms.end() - settings.frames, cpu_ms.end());
  volume_->forget_history();
  f.volume = volume_->render_offscreen(camera, f.volume_settings, settings.size);
  f.volume->passes = f.timing->medians();
  return f;
}

SceneFrame SceneRenderer::render_surfaces(const Camera& camera, const SceneSettings& settings) {
  if (!settings.surface_mode) throw std::invalid_argument("SceneRenderer: a surface frame without a surface mode");
  const surface::SurfaceMode& mode = *settings.surface_mode;
  SceneFrame f;
  f.volume_settings = settings.volume;
  if (!mode.gpu()) {
    const SurfaceScene& scene = *scene_.surfaces;
    f.device = "CPU path tracer (double precision)";
    validate_float_range(scene);  // double arithmetic, but the image is float32
    reference::PathTracerSettings path = settings.path;
    path.width = settings.size.width;
    path.height = settings.size.height;
    f.path = reference::path_trace(scene, camera, path);
    return f;
  }
  const vk::Device& gpu = device();
  gpu_identity(f);
  const surface::SurfaceBackendInfo& backend = *mode.backend;
  const std::string name(mode.name);
  if (const std::string problem = backend.device_problem(gpu); !problem.empty())
    throw vk::NoSuitableDevice(problem + ": " + setting("mode", name) + " needs " + std::string(backend.needs));
  surfaces_ = &surfaces_for(settings.surface_options);
  set_shadows(*surfaces_, settings.shadows, device_name_);
  if (settings.sequence) {
    render_surface_sequence(f, camera, settings);
    return f;
  }
  if (settings.interactive) {
    f.surfaces = surfaces_->render_offscreen(camera, name, settings.size, settings.supersample);
    return f;
  }
  // Each timed frame is read back (a GI mode's image is the mean of its still frames): the image
  // is the last timed frame's.
  surface::SurfaceRenderer::Offscreen image;
  f.timing = timed(settings, [&] {
    surfaces_->forget_shading();  // each timed frame costs what a moving camera's does
    image = surfaces_->render_offscreen(camera, name, settings.size, settings.supersample);
    return image.passes;
  });
  image.passes = f.timing->medians();
  f.surfaces = std::move(image);
  return f;
}

surface::SurfaceRenderer& SceneRenderer::surfaces_for(const surface::SurfaceOptions& options) {
  std::unique_ptr<surface::SurfaceRenderer>& r = surface_renderers_[options];
  if (!r) r = std::make_unique<surface::SurfaceRenderer>(device(), *scene_.surfaces, options);
  return *r;
}

const surface::SurfaceRenderer& SceneRenderer::surface_renderer(const surface::SurfaceOptions& options) {
  if (!scene_.surfaces || scene_.volume) throw std::logic_error("SceneRenderer::surface_renderer: a scene of surfaces alone has one");
  return surfaces_for(options);
}

void SceneRenderer::render_surface_sequence(SceneFrame& f, const Camera& camera, const SceneSettings& settings) {
  const SurfaceSequence& q = *settings.sequence;
  surface::SurfaceRenderer& r = *surfaces_;
  const std::string mode(settings.surface_mode->name);
  const bool gi = settings.surface_mode->gi != frame::SurfaceGi::None;
  r.set_shading_rate(q.lod_bias, q.block_budget);
  r.set_msa_amortization(q.amortize);
  r.set_msa_charts(q.charts);
  r.resize(settings.size);
  const vk::Device& gpu = device();
  // One frame drawn and timed; its image stays on the GPU.
  const auto draw = [&](const Camera& c) {
    vk::GpuTimer timer(gpu, 16);
    timer.submit_and_wait([&](VkCommandBuffer cmd) { r.record(cmd, c, mode, timer); });
    return timer.read();
  };
  timing::warm_up([&] { return vk::total_gpu_ms(draw(camera)); }, settings.warm_up_seconds.value_or(timing::kTimedWarmUpSeconds));
  if (gi) {  // the reservoirs gather over the still camera's frames, as in the window
    r.reset_gi();
    for (uint32_t i = 0; i + settings.frames < q.gi_frames; ++i) draw(camera);
  }
  if (q.camera_path) {
    r.set_msa_amortization(q.amortize);  // counted from the path's first frame: the warm-up's are forgotten
    for (uint32_t i = 0; i < settings.frames; ++i) draw(q.camera_path(i));
  }
  uint32_t index = 0;
  f.timing = timing::time_frames(settings.frames, [&] {
    if (!gi && !q.keep_shading && !q.camera_path) r.forget_shading();  // each frame costs what a moving camera's does
    const std::vector<vk::PassTiming> passes = draw(q.camera_path ? q.camera_path(settings.frames + index) : camera);
    ++index;
    f.frame_shaded.push_back(r.read_counts().shaded);
    return passes;
  });
  surface::SurfaceRenderer::Offscreen image;
  image.width = settings.size.width;
  image.height = settings.size.height;
  image.rgba.resize(size_t(image.width) * image.height * 4);
  vk::read_image(gpu, r.display(), sizeof(float) * 4, std::as_writable_bytes(std::span(image.rgba)));
  image.passes = f.timing->medians();
  image.counts = r.read_counts();
  image.plan = r.last_plan();
  f.surfaces = std::move(image);
}

SceneFrame SceneRenderer::render_mixed(const Camera& camera, const SceneSettings& settings) {
  if (!settings.volume_mode) throw std::invalid_argument("SceneRenderer: a mixed frame without a volume mode");
  const std::string surface_mode = settings.surface_mode ? std::string(settings.surface_mode->name) : "forward";
  SceneFrame f;
  f.volume_settings = settings.volume;
  if (!settings.volume_mode->gpu()) {
    f.device = kVolumeReference;
    const bool shadows = settings.shadows.value_or(surface::surface_contents(*scene_.surfaces).casts_shadows());
    f.mixed = render_mixed_reference(*scene_.volume, *scene_.surfaces, camera, settings.volume.resolve, settings.size, shadows);
    return f;
  }
  const vk::Device& gpu = device();
  gpu_identity(f);
  resolve_auto(f.volume_settings, settings, gpu);
  if (!mixed_) {
    mixed_ = std::make_unique<MixedRenderer>(gpu, *scene_.volume, *scene_.surfaces);
    ++uploads_.meshes;
  }
  set_shadows(mixed_->surface_renderer(), settings.shadows, device_name_);
  if (settings.interactive) {
    f.mixed = mixed_->render(camera, f.volume_settings, settings.size, surface_mode);
    return f;
  }
  // Each timed frame is the whole mixed frame, read back (the volume's rays end at the surfaces'
  // depth read back from the GPU): the image is the last timed frame's.
  MixedFrame last;
  f.timing = timed(settings, [&] {
    mixed_->surface_renderer().forget_shading();  // each timed frame costs what a moving camera's does
    mixed_->volume_renderer().forget_history();
    last = mixed_->render(camera, f.volume_settings, settings.size, surface_mode);
    return last.passes;
  });
  last.passes = f.timing->medians();
  f.mixed = std::move(last);
  return f;
}

SceneFrame SceneRenderer::reference(const Camera& camera, const SceneSettings& settings, const SceneFrame& drawn) const {
  if (!scene_.volume) throw std::logic_error("SceneRenderer::reference: surfaces alone have the path tracer, a mode of their own");
  SceneFrame f;
  f.device = kVolumeReference;
  f.volume_settings = drawn.volume_settings;
  if (scene_.surfaces) {
    if (!drawn.mixed) throw std::logic_error("SceneRenderer::reference: `drawn` is not this scene's frame");
    f.mixed = render_mixed_reference(*scene_.volume, *scene_.surfaces, camera, drawn.volume_settings.resolve, settings.size,
                                     drawn.mixed->shadows);
  } else {
    f.volume = volume::reference_backend().render(*scene_.volume, camera, drawn.volume_settings.resolve, settings.size,
                                                  scene_.analytic_field);
  }
  return f;
}

}  // namespace prismoid::mixed
