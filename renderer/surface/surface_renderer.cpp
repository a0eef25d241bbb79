#include "renderer/surface/surface_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/geometric.hpp>
#include <stdexcept>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "scene/input_error.hpp"

namespace prismoid::surface {

std::vector<std::string> surface_modes(const vk::Device& device) {
  std::vector<std::string> modes;
  if (device.capabilities().geometry_shader) modes.push_back("forward");
  if (htex_device_problem(device).empty())
    for (const char* m : {"htex", "htex-gi", "htex-gi-unbiased", "htex-pt"}) modes.push_back(m);
  if (texel_device_problem(device).empty()) modes.push_back("texel");
  if (msa_device_problem(device).empty()) modes.push_back("msa");
  return modes;
}

ShadingReuse plan_shading_reuse(const ReuseInputs& in) {
  if (in.first_frame) return {true, "shaded: the first frame of this mode"};
  if (in.settings_changed) return {true, "shaded again: the shadows setting changed"};
  if (in.eye_moved && in.amortized) return {false, "reused while the eye moves: amortized (every n-th frame shades again)"};
  if (in.eye_moved) return {true, "shaded again: the eye moved (the shading depends on it)"};
  return {false, "reused: the eye did not move"};
}

double htex_texels_per_unit(const SurfaceScene& scene) {
  const Bounds b = bounds_of(scene);
  const double diagonal = glm::length(b.max - b.min);
  return diagonal > 0.0 && std::isfinite(diagonal) ? kHtexTexelsPerDiagonal / diagonal : 1.0;
}

SurfaceRenderer::SurfaceRenderer(const vk::Device& device, const SurfaceScene& scene)
    : device_(device), source_(scene), scene_(upload(device, scene)), modes_(surface_modes(device)) {
  if (modes_.empty()) throw vk::NoSuitableDevice(device.capabilities().name + " can draw no surface mode (no geometryShader feature)");
  shadows_ = can_shadow() && scene_.point_light_count + scene_.directional_light_count + scene_.emitter_count > 0;
}

bool SurfaceRenderer::can_shadow() const { return device_.ray_tracing_enabled(); }

void SurfaceRenderer::set_shadows(bool on) {
  if (on && !can_shadow())
    throw vk::NoSuitableDevice(device_.capabilities().name + " has no ray tracing (VK_KHR_ray_tracing_pipeline and "
                               "VK_KHR_acceleration_structure): shadows need it");
  shadows_ = on;
  for (HtexPass* pass : {htex_.get(), gi_pass_.get()})
    if (pass) {
      HtexSettings settings = pass->settings();
      settings.shadows = on;
      pass->set_settings(settings);
    }
}

SurfaceRenderer::~SurfaceRenderer() = default;

std::string SurfaceRenderer::mode_problem(const std::string& mode) const {
  if (std::find(modes_.begin(), modes_.end(), mode) != modes_.end()) return {};
  std::string known;
  for (const std::string& m : modes_) known += (known.empty() ? "" : ", ") + m;
  return "unknown surface mode " + mode + " (this device draws: " + known + ")";
}

void SurfaceRenderer::resize(VkExtent2D extent) {
  if (extent.width == 0 || extent.height == 0) throw InputError("surface image", "the image size must be positive");
  if (extent.width == extent_.width && extent.height == extent_.height) return;
  extent_ = extent;
  forward_targets_.reset();
  shadowed_targets_.reset();
  htex_targets_.reset();
  texel_targets_.reset();
  msa_targets_.reset();
  display_ = nullptr;
}

void SurfaceRenderer::record(VkCommandBuffer cmd, const Camera& camera, const std::string& mode, vk::GpuTimer& timer) {
  if (const std::string problem = mode_problem(mode); !problem.empty()) throw InputError("--mode " + mode, problem);
  if (mode != last_mode_) last_eye_.reset();  // another mode drew in between: shade afresh
  last_mode_ = mode;
  const bool htex_mode = mode.rfind("htex", 0) == 0;
  if ((shadows_ || htex_mode || mode == "texel" || mode == "msa") && !accel_)
    accel_ = std::make_unique<rt::SceneAccel>(device_, source_);  // origin: the bounds centre, as scene_.origin
  if (htex_mode && mode != "htex") {
    record_htex_gi(cmd, camera, mode, timer);
    return;
  }
  if (mode == "texel") {
    record_texel(cmd, camera, timer);
    return;
  }
  if (mode == "msa") {
    record_msa(cmd, camera, timer);
    return;
  }
  if (mode == "htex") {
    if (!htex_) {
      htex_geometry_ = std::make_unique<HtexGeometry>(source_, htex::LayoutOptions{.texels_per_unit = htex_texels_per_unit(source_)});
      HtexSettings settings;
      settings.shadows = shadows_;
      htex_ = std::make_unique<HtexPass>(device_, *htex_geometry_, settings);
    }
    if (!htex_targets_) htex_targets_ = std::make_unique<HtexTargets>(create_htex_targets(device_, extent_));
    last_reuse_ = plan_reuse(camera);
    if (last_reuse_.invalidate) htex_->invalidate_shading();
    if (!htex_->settings().reuse_shading || htex_->settings().lod_bias != lod_bias_) {
      HtexSettings settings = htex_->settings();
      settings.reuse_shading = true;
      settings.lod_bias = lod_bias_;
      htex_->set_settings(settings);
    }
    htex_->record(cmd, scene_, accel_->tlas(), *htex_targets_, camera, timer);
    last_eye_ = camera.eye;
    last_shadows_ = shadows_;
    display_ = &htex_targets_->color;
    return;
  }
  if (shadows_) {
    if (!shadowed_) shadowed_ = std::make_unique<ShadowedForwardPass>(device_);
    if (!shadowed_targets_) shadowed_targets_ = std::make_unique<ShadowedForwardTargets>(create_shadowed_forward_targets(device_, extent_));
    shadowed_->record(cmd, scene_, *accel_, *shadowed_targets_, camera, {}, timer);
    display_ = &shadowed_targets_->color;
    return;
  }
  if (!forward_) forward_ = std::make_unique<ForwardPass>(device_);
  if (!forward_targets_) forward_targets_ = std::make_unique<ForwardTargets>(create_forward_targets(device_, extent_));
  forward_->record(cmd, scene_, *forward_targets_, camera, {}, timer);
  display_ = &forward_targets_->color;
}

void SurfaceRenderer::set_shading_rate(float lod_bias, uint32_t msa_budget) {
  lod_bias_ = lod_bias;
  msa_budget_ = msa_budget;
  last_eye_.reset();  // shade afresh
}

void SurfaceRenderer::set_msa_charts(msa::Parametrization charts) {
  if (charts == msa_charts_) return;
  msa_charts_ = charts;
  msa_.reset();  // rebuilt with the new charts at the next msa frame
  meshlets_.reset();
  last_eye_.reset();
}

void SurfaceRenderer::set_msa_amortization(uint32_t every_n_frames) {
  msa_amortization_ = every_n_frames;
  last_eye_.reset();  // shade afresh
}

ShadingReuse SurfaceRenderer::plan_reuse(const Camera& camera, bool amortized) const {
  ReuseInputs in;
  in.first_frame = !last_eye_;
  in.settings_changed = last_shadows_ != shadows_;
  in.eye_moved = last_eye_ && *last_eye_ != camera.eye;
  in.amortized = amortized;
  return plan_shading_reuse(in);
}

void SurfaceRenderer::record_texel(VkCommandBuffer cmd, const Camera& camera, vk::GpuTimer& timer) {
  if (!texel_) {
    texel_atlas_ = std::make_unique<texel::TexelAtlas>(build_texel_atlas_for(device_, source_));
    TexelSettings settings;
    settings.shadows = shadows_;
    texel_ = std::make_unique<TexelPass>(device_, *texel_atlas_, settings);
  }
  if (!texel_targets_) texel_targets_ = std::make_unique<TexelTargets>(create_texel_targets(device_, extent_));
  TexelSettings settings = texel_->settings();
  settings.shadows = shadows_;
  settings.lod_bias = lod_bias_;
  // The planner's rule (plan_shading_reuse): a still eye reuses every tile shaded since the last
  // change, whatever its age; a moved eye shades again.
  last_reuse_ = plan_reuse(camera);
  settings.max_age = last_reuse_.invalidate ? 1u : 0xffffffffu;
  texel_->set_settings(settings);
  if (last_reuse_.invalidate) texel_->invalidate_shading();
  texel_->record(cmd, scene_, accel_->tlas(), *texel_targets_, camera, timer);
  last_eye_ = camera.eye;
  last_shadows_ = shadows_;
  display_ = &texel_targets_->color;
}

void SurfaceRenderer::record_msa(VkCommandBuffer cmd, const Camera& camera, vk::GpuTimer& timer) {
  if (!msa_) {
    meshlets_ = std::make_unique<msa::MeshletSet>(msa::build_meshlets(source_, {.parametrization = msa_charts_}));
    MsaSettings settings;
    settings.shadows = shadows_;
    // As many superblocks (1 MiB each) as one storage buffer holds, up to 256 (16 M texels).
    settings.superblocks = uint32_t(std::clamp<uint64_t>(device_.capabilities().max_storage_buffer_range / (uint64_t(256) * 256 * 16), 1, 256));
    msa_ = std::make_unique<MsaPass>(device_, *meshlets_, settings);
  }
  if (!msa_targets_) msa_targets_ = std::make_unique<MsaTargets>(create_msa_targets(device_, extent_));
  MsaSettings settings = msa_->settings();
  settings.shadows = shadows_;
  settings.budget_texels = msa_budget_;
  settings.shade_every = msa_amortization_;
  msa_->set_settings(settings);
  // The planner's rule: a still eye reuses every block's shading; a moved eye shades them again,
  // unless amortized (then only the first frame and changed settings do, and shade_every).
  last_reuse_ = plan_reuse(camera, msa_amortization_ > 0);
  if (last_reuse_.invalidate) msa_->invalidate_shading();
  msa_->record(cmd, scene_, accel_->tlas(), *msa_targets_, camera, timer);
  last_eye_ = camera.eye;
  last_shadows_ = shadows_;
  display_ = &msa_targets_->color;
}

RestirGiSettings SurfaceRenderer::gi_settings(const std::string& mode) {
  RestirGiSettings s;
  s.unbiased = mode == "htex-gi-unbiased";
  if (mode == "htex-pt") {  // one fresh bounce sample per texel and frame, nothing reused
    s.temporal = false;
    s.fallback = false;
    s.spatial_neighbours = 0;
  }
  return s;
}

void SurfaceRenderer::reset_gi() {
  if (gi_) gi_->reset();
  gi_frame_ = 0;
}

void SurfaceRenderer::record_htex_gi(VkCommandBuffer cmd, const Camera& camera, const std::string& mode, vk::GpuTimer& timer) {
  if (!gi_pass_) {
    if (!htex_geometry_)
      htex_geometry_ = std::make_unique<HtexGeometry>(source_, htex::LayoutOptions{.texels_per_unit = htex_texels_per_unit(source_)});
    HtexSettings settings;
    settings.shadows = shadows_;
    settings.indirect = true;
    settings.sky_ambient = false;  // the sky arrives through GI's bounce rays, occluded
    settings.pool_pages = kGiPoolPages;
    gi_pass_ = std::make_unique<HtexPass>(device_, *htex_geometry_, settings);
    gi_ = std::make_unique<HtexGi>(device_, *gi_pass_, scene_, *accel_);
  }
  if (!htex_targets_) htex_targets_ = std::make_unique<HtexTargets>(create_htex_targets(device_, extent_));
  gi_pass_->record_marking(cmd, scene_, accel_->tlas(), *htex_targets_, camera, timer);
  gi_pass_->record_allocation(cmd, *htex_targets_, timer);
  gi_pass_->record_shading(cmd, *htex_targets_, timer);
  gi_->record(cmd, camera, extent_, gi_frame_++, gi_settings(mode), &timer);
  gi_pass_->record_gather(cmd, *htex_targets_, timer);
  display_ = &htex_targets_->color;
}

SurfaceRenderer::FrameCounts SurfaceRenderer::read_counts() const {
  FrameCounts c;
  const HtexPass* pass = last_mode_ == "htex" ? htex_.get() : last_mode_.rfind("htex", 0) == 0 ? gi_pass_.get() : nullptr;
  if (pass) {
    const HtexCounters h = pass->read_counters();
    c.shaded = h.shaded_texels;
    c.mode_bytes = h.pool_bytes + pass->tables().bytes + (pass == gi_pass_.get() ? gi_->reservoir_bytes() + gi_->persistent_bytes() : 0);
    c.detail = std::to_string(h.marked_shadels) + " shadels marked, " + std::to_string(h.resident_groups) + " groups resident, " +
               std::to_string(h.allocated_pages) + " pages allocated, " + std::to_string(h.released_pages) + " released" +
               (h.bias_levels ? ", bias " + std::to_string(h.bias_levels) + " levels" : "") + (h.overflow ? ", POOL OVERFLOW" : "");
    if (pass == htex_.get())
      c.detail += "; " + std::to_string(h.reused_shadels) + " shadels reused, " + std::to_string(h.shaded_shadels) + " shaded (" +
                  last_reuse_.reason + ")";
    if (pass == gi_pass_.get()) c.detail += "; GI " + std::to_string(gi_frame_) + " frames";
  } else if (last_mode_ == "texel" && texel_) {
    const TexelCounters t = texel_->read_counters();
    c.shaded = t.shaded_texels;
    c.mode_bytes = t.atlas_bytes;
    c.detail = std::to_string(t.queued_tiles) + " tiles shaded (" + last_reuse_.reason + "); atlas " + std::to_string(texel_atlas_->width) +
               " x " + std::to_string(texel_atlas_->height) + ", " + std::to_string(texel_atlas_->levels) + " levels, " +
               std::to_string(texel_atlas_->charts.size()) + " charts" + (t.hole_pixels ? ", HOLES " + std::to_string(t.hole_pixels) : "");
  } else if (last_mode_ == "msa" && msa_) {
    const MsaCounters m = msa_->read_counters();
    c.shaded = m.shaded_texels;
    c.mode_bytes = m.atlas_bytes;
    c.detail = std::to_string(m.seen_meshlets) + " of " + std::to_string(meshlets_->meshlets.size()) + " meshlets seen, " +
               std::to_string(m.shaded_blocks) + " blocks shaded (" + last_reuse_.reason + "), " + std::to_string(m.allocated_blocks) +
               " allocated, " + std::to_string(m.released_blocks) + " released; " + std::to_string(m.free_superblocks) + " superblocks free" +
               (m.hole_pixels ? ", ATLAS FULL: " + std::to_string(m.hole_pixels) + " pixels unshaded" : "");
  } else if (last_mode_ == "forward" && shadows_ && shadowed_) {
    c.shaded = shadowed_->read_shading_invocations();
  } else if (last_mode_ == "forward" && forward_) {
    c.shaded = forward_->read_fragment_invocations();
  }
  return c;
}

const vk::Image& SurfaceRenderer::display() const {
  if (!display_) throw std::logic_error("SurfaceRenderer::display before the first record");
  return *display_;
}

}  // namespace prismoid::surface
