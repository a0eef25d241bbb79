#include "app/bench/surface_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>

#include "app/common/cli_args.hpp"
#include "app/common/surface_args.hpp"
#include "renderer/metrics/flip.hpp"
#include "renderer/metrics/image_error.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/reference/direct_light.hpp"
#include "renderer/reference/path_tracer.hpp"
#include "renderer/surface/surface_modes.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/timing/frame_timing.hpp"
#include "renderer/vk/device.hpp"
#include "scene/surface_generators.hpp"
#include "scene/surface_refine.hpp"

namespace prismoid::bench {

namespace {

SurfaceScene load_scene(const std::string& name) {
  app::ParsedArgs one;
  one.files.push_back(name);
  return app::surface_scene_from(one, "bench");
}

// What the window and a PNG show of a linear radiance image: each colour channel clamped to
// [0, 1]. Surface rows are compared on it, as the report says (display RGB, peak 1): in linear
// radiance an aliased edge of a light at radiance 17 held 90% of every row's error.
std::vector<float> as_displayed(const std::vector<float>& rgba) {
  std::vector<float> shown(rgba);
  for (size_t i = 0; i < shown.size(); ++i)
    if (i % 4 != 3) shown[i] = std::clamp(shown[i], 0.0f, 1.0f);
  return shown;
}

struct ReferenceImage {
  std::vector<float> rgba;
  double ms = 0.0;
};

ReferenceImage reference_image(const SurfaceScene& scene, VkExtent2D extent, uint32_t supersample, bool shadows) {
  reference::DirectLightOptions options;
  options.shadows = shadows;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<glm::dvec3> ref3 =
      reference::supersampled_direct_light(scene, scene.camera, extent.width, extent.height, supersample, options);
  ReferenceImage r;
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  r.rgba.resize(ref3.size() * 4);
  for (size_t p = 0; p < ref3.size(); ++p) {
    for (int c = 0; c < 3; ++c) r.rgba[4 * p + c] = float(ref3[p][c]);
    r.rgba[4 * p + 3] = 1.0f;
  }
  return r;
}

// What a GI mode converges to: emission + direct + one bounce, all with exact visibility: the
// path tracer with at most two reflections (CPU, double).
ReferenceImage path_reference(const SurfaceScene& scene, VkExtent2D extent, uint32_t spp) {
  reference::PathTracerSettings settings;
  settings.width = extent.width;
  settings.height = extent.height;
  settings.samples_per_pixel = spp;
  settings.max_bounces = 2;
  const reference::PathTracedImage image = reference::path_trace(scene, scene.camera, settings);
  ReferenceImage r;
  r.ms = image.seconds * 1000.0;
  r.rgba.resize(image.mean.size() * 4);
  for (size_t p = 0; p < image.mean.size(); ++p) {
    for (int c = 0; c < 3; ++c) r.rgba[4 * p + c] = float(image.mean[p][c]);
    r.rgba[4 * p + 3] = 1.0f;
  }
  return r;
}

// `n` point lights on a Fibonacci sphere of 1.5 half-diagonals around the scene's centre, white,
// together giving about the irradiance of the default headlight where half of them are seen.
SurfaceScene with_point_lights(SurfaceScene scene, uint32_t n) {
  const Bounds b = bounds_of(scene);
  const glm::dvec3 centre = 0.5 * (b.min + b.max);
  const double r = 0.75 * glm::length(b.max - b.min);
  scene.point_lights.clear();
  scene.directional_lights.clear();
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (uint32_t i = 0; i < n; ++i) {
    const double y = 1.0 - 2.0 * (i + 0.5) / n, ring = std::sqrt(std::max(0.0, 1.0 - y * y)), phi = golden * i;
    PointLight light;
    light.position = centre + r * glm::dvec3(ring * std::cos(phi), y, ring * std::sin(phi));
    light.intensity = glm::dvec3(2.0 * 3.14159265358979323846 * kHeadlightScale * r * r / n);
    scene.point_lights.push_back(light);
  }
  return scene;
}

const surface::SurfaceMode& mode_of(const std::string& name) { return *surface::find_surface_mode(name); }
// The modes with indirect light are held to the path tracer and accumulate over still frames.
bool gi_mode(const std::string& mode) {
  const surface::SurfaceMode* m = surface::find_surface_mode(mode);
  return m && m->gi != frame::SurfaceGi::None;
}
// What of SurfaceTuning the mode's backend honours (surface::TuningKnob).
uint32_t knobs(const std::string& mode) { return mode_of(mode).backend->tuning; }

// The camera turned about its target and up axis by `degrees`.
Camera orbited(const Camera& camera, double degrees) {
  Camera c = camera;
  const glm::dvec3 axis = glm::normalize(camera.up);
  const glm::dvec3 offset = camera.eye - camera.target;
  const double a = glm::radians(degrees), cs = std::cos(a), sn = std::sin(a);
  // Rodrigues' rotation of the offset about the axis.
  c.eye = camera.target + offset * cs + glm::cross(axis, offset) * sn + axis * glm::dot(axis, offset) * (1.0 - cs);
  return c;
}

}  // namespace

std::string surface_reference_kind(const std::string& mode) {
  if (gi_mode(mode)) return "the CPU path tracer with at most two reflections (emission + direct + one bounce, exact shadows)";
  return "direct light (CPU, double; with the same shadow rays as the GPU where shadows=on)";
}

std::vector<BenchRow> bench_surfaces(const vk::Device& device, const SurfaceBenchOptions& options) {
  std::vector<BenchRow> rows;
  const VkExtent2D extent{options.size.width, options.size.height};
  for (const std::string& name : options.scenes) {
    SurfaceScene raw = load_scene(name);
    if (options.max_triangle_pixels > 0.0)
      raw = refine_large_triangles(raw, raw.camera, extent.width, extent.height, options.max_triangle_pixels);
    if (options.extra_lights > 0) raw = with_point_lights(std::move(raw), options.extra_lights);
    const SurfaceScene scene = with_default_lighting(raw, raw.camera);
    const Camera& camera = scene.camera;
    std::map<std::string, ReferenceImage> references;
    // Every row's frames through the renderer facade, on the bench's device.
    mixed::SceneRenderer renderer({.surfaces = &scene}, device);
    const surface::SurfaceRenderer& main_renderer = renderer.surface_renderer();
    std::vector<bool> shadow_settings;
    if (options.shadows_off || !main_renderer.can_shadow()) shadow_settings.push_back(false);
    if (options.shadows_on && main_renderer.can_shadow()) shadow_settings.push_back(true);
    struct Run {
      std::string mode;
      uint32_t budget = 0;  // 0: the mode's own rate
      bool still = false;   // frames reuse a still camera's shading
      bool moving = false;  // the camera orbits (options.motion_degrees per frame)
      uint32_t amortize = 0;  // msa: shade every n-th frame
      msa::Parametrization charts = msa::Parametrization::Projection;  // msa
      double sf = 1.0;        // shading-rate factor (SurfaceBenchOptions::shading_scales)
      uint32_t atlas = 0;     // fastatlas: the atlas side (0: the backend's default)
      uint32_t refresh = 0;   // fastatlas: temporal reuse refreshed every n frames (0: off)
    };
    std::vector<Run> runs;
    for (const std::string& mode : main_renderer.modes()) {
      if (!options.modes.empty() && std::find(options.modes.begin(), options.modes.end(), mode) == options.modes.end()) continue;
      // Shading-rate rows for the modes whose backend takes a rate (texture space, without GI).
      const bool texture_space = !gi_mode(mode) && (knobs(mode) & (surface::kTuneLodBias | surface::kTuneBlockBudget)) != 0;
      const std::vector<msa::Parametrization> chart_kinds =
          knobs(mode) & surface::kTuneCharts ? options.msa_charts : std::vector{msa::Parametrization::Projection};
      std::vector<uint32_t> atlases{0u};
      if (mode == "fastatlas" && !options.fastatlas_atlases.empty()) atlases = options.fastatlas_atlases;
      for (const uint32_t atlas : atlases)
        for (const msa::Parametrization charts : chart_kinds) {
          runs.push_back({mode, 0u, false, false, 0u, charts, 1.0, atlas});
          if (options.shading_budget > 0 && texture_space) runs.push_back({mode, options.shading_budget, false, false, 0u, charts, 1.0, atlas});
          if (options.still_rows && texture_space) runs.push_back({mode, 0u, true, false, 0u, charts, 1.0, atlas});
          if (options.motion_degrees > 0.0 && !gi_mode(mode)) runs.push_back({mode, 0u, false, true, 0u, charts, 1.0, atlas});
          if (options.motion_degrees > 0.0 && (knobs(mode) & surface::kTuneAmortize))
            for (const uint32_t n : options.msa_amortization) runs.push_back({mode, 0u, false, true, n, charts, 1.0, atlas});
          if (options.motion_degrees > 0.0 && mode == "fastatlas")
            for (const uint32_t n : options.fastatlas_refresh) runs.push_back({mode, 0u, false, true, 0u, charts, 1.0, atlas, n});
          for (const double sf : options.shading_scales)
            if (texture_space && sf < 1.0) runs.push_back({mode, 0u, false, false, 0u, charts, sf, atlas});
        }
    }
    // Rows at the modes' own rate first: the SF rows of block-budget modes size their budgets from them.
    std::stable_sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.sf > b.sf; });
    std::map<std::string, uint64_t> unbiased_shaded;  // mode/shadows -> shaded samples at the mode's own rate
    uint32_t covered_pixels = 0;                      // of the scene's first frame
    for (const bool shadows : shadow_settings)
    for (const Run& run : runs) {
      const std::string& mode = run.mode;
      uint32_t budget = run.budget;
      if (budget == SurfaceBenchOptions::kBudgetCoveredPixels) budget = std::max(1u, covered_pixels);
      const std::string rate_key = mode + (shadows ? "/on" : "/off") + (run.atlas ? "/" + std::to_string(run.atlas) : "") + "/" +
                                   msa::parametrization_name(run.charts);
      float lod_bias = 0.0f;
      const bool block_budget = (knobs(mode) & surface::kTuneBlockBudget) != 0;  // a budget of block texels, not a level bias
      if (budget > 0 && !block_budget && unbiased_shaded.count(rate_key) && unbiased_shaded.at(rate_key) > budget)
        lod_bias = float(0.5 * std::log2(double(unbiased_shaded.at(rate_key)) / double(budget)));
      if (run.sf < 1.0) {
        if (!block_budget) lod_bias = float(-std::log2(run.sf));
        else if (unbiased_shaded.count(rate_key)) budget = std::max(1u, uint32_t(double(unbiased_shaded.at(rate_key)) * run.sf * run.sf));
      }
      // The CPU reference of what the mode computes, once per shadow setting.
      if (gi_mode(mode) && !shadows) continue;  // GI's bounce rays see occlusion: only with shadows
      const std::string ref_key = gi_mode(mode) ? "path" : shadows ? "shadows" : "none";
      if (!references.count(ref_key))
        references[ref_key] = gi_mode(mode) ? path_reference(scene, extent, options.path_spp)
                                            : reference_image(scene, extent, options.supersample, shadows);
      const ReferenceImage& ref = references.at(ref_key);
      const std::vector<float>& reference = ref.rgba;
      const double reference_ms = ref.ms;
      // The row's frames: warm-up, a GI mode's gathering frames of the still camera (the row
      // measures the frame after options.gi_frames of them, as in the window), a moving row's
      // `frames` frames of the orbit (amortization counts from its first, so with n dividing
      // 2 * frames the measured last frame, at the scene's camera, is the stalest of its cycle:
      // its error is the amortization's worst), then the timed frames, the image the last one's.
      mixed::SceneSettings settings;
      settings.size = extent;
      settings.surface_mode = &mode_of(mode);
      if (run.atlas != 0) settings.surface_options["atlas"] = std::to_string(run.atlas);
      if (run.refresh != 0) settings.surface_options["atlas-refresh"] = std::to_string(run.refresh);
      settings.shadows = shadows;
      settings.frames = options.frames;
      settings.warm_up_seconds = options.warm_up_seconds;
      mixed::SurfaceSequence sequence{.lod_bias = lod_bias,
                                      .block_budget = block_budget ? budget : 0u,
                                      .amortize = run.amortize,
                                      .charts = run.charts,
                                      .keep_shading = run.still,
                                      .gi_frames = options.gi_frames};
      const uint32_t orbit_frames = 2 * options.frames;
      if (run.moving)
        sequence.camera_path = [&](uint32_t i) { return orbited(camera, double(orbit_frames - 1 - i) * options.motion_degrees); };
      settings.sequence = sequence;
      const mixed::SceneFrame drawn = renderer.render(camera, settings);
      const mixed::SurfaceStats& stats = *drawn.stats.surfaces;
      if (covered_pixels == 0) covered_pixels = uint32_t(stats.covered_pixels);
      const std::vector<float>& image = drawn.surfaces->rgba;
      uint64_t shaded_sum = 0;
      for (const uint64_t n : drawn.frame_shaded) shaded_sum += n;
      BenchRow m;
      m.dataset = scene.name;
      for (const SceneMesh& mesh : scene.meshes) m.cells += mesh.triangles.size();
      m.sweep = "surfaces";
      m.quantity = "color";
      m.mode = mode;
      m.settings = shadows ? "shadows=on" : "shadows=off";
      if (options.extra_lights > 0) m.settings += " lights=" + std::to_string(options.extra_lights);
      if (options.max_triangle_pixels > 0.0) m.settings += " refined=" + app::json_number(options.max_triangle_pixels);
      if (run.still) m.settings += " camera=still";
      if (run.moving) m.settings += " camera=moving(" + app::json_number(options.motion_degrees) + "deg/frame)";
      if (run.amortize > 0) m.settings += " amortize=" + std::to_string(run.amortize);
      if (run.charts != msa::Parametrization::Projection) m.settings += std::string(" charts=") + msa::parametrization_name(run.charts);
      if (run.atlas != 0) m.settings += " atlas=" + std::to_string(run.atlas);
      if (run.refresh != 0) m.settings += " refresh=" + std::to_string(run.refresh);
      if (run.sf < 1.0) m.settings += " sf=" + app::json_number(run.sf);
      if (budget > 0 && run.sf == 1.0)
        m.settings += " budget=" + std::to_string(budget) + (block_budget ? "" : " lod-bias=" + std::to_string(lod_bias));
      if (gi_mode(mode)) m.settings += " frames=" + std::to_string(stats.gi_frames);
      m.ordering = "-";
      m.width = extent.width;
      m.height = extent.height;
      set_times(m, *drawn.timing);
      m.mesh_bytes = stats.gpu_scene_bytes;
      const surface::SurfaceRenderer::FrameCounts& counts = drawn.surfaces->counts;
      m.shaded = (shaded_sum + options.frames / 2) / options.frames;  // the mean over the measured frames
      if (budget == 0 && run.sf == 1.0 && !run.still && !run.moving && run.refresh == 0)
        unbiased_shaded[rate_key] = counts.shaded;
      // FastAtlas's atlasing steps (its own timestamps, the last measured frame) after the frame's
      // passes, named "atlasing/<step>": parts of "atlasing", not further passes. The atlases'
      // stretch between screen and atlas (FastAtlas, msa), and FastAtlas's fill, go to `space`.
      for (const auto& [stat, value] : counts.stats) {
        if (stat.rfind("atlasing_", 0) == 0 && std::holds_alternative<double>(value))
          m.passes += ";atlasing/" + stat.substr(9, stat.size() - 9 - 3) + "=" + app::json_number(std::get<double>(value));
        if ((stat == "stretch_l2" || stat == "stretch_linf" || stat == "atlas_fill") && std::holds_alternative<double>(value))
          m.space += (m.space.empty() ? "" : ";") + stat + "=" + app::json_number(std::get<double>(value));
      }
      m.mode_bytes = counts.mode_bytes;
      const std::vector<float> shown = as_displayed(image), shown_reference = as_displayed(reference);
      m.error = reference::image_error(shown, shown_reference, 1.0, 4, 3);
      m.ssim = reference::ssim(shown, shown_reference, extent.width, extent.height, 1.0, 4, 3);
      m.flip = reference::flip(shown, shown_reference, extent.width, extent.height, 4).mean;
      m.peak = 1.0;
      m.reference_ms = reference_ms;
      std::cout << m.dataset << " surfaces color " << m.mode << " " << m.width << "x" << m.height << ": " << m.ms_median
                << " ms GPU, RMSE " << m.error.rmse << std::endl;
      rows.push_back(std::move(m));
    }
  }
  return rows;
}

}  // namespace prismoid::bench
