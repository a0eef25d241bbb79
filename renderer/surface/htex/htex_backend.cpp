#include "renderer/surface/htex/htex_backend.hpp"

#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "renderer/surface/gi/htex_gi.hpp"
#include "renderer/surface/htex/htex_pass.hpp"
#include "renderer/vk/device.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

double htex_texels_per_unit(const SurfaceScene& scene) {
  const Bounds b = bounds_of(scene);
  const double diagonal = glm::length(b.max - b.min);
  return diagonal > 0.0 && std::isfinite(diagonal) ? kHtexTexelsPerDiagonal / diagonal : 1.0;
}

RestirGiSettings restir_gi_settings(frame::SurfaceGi gi) {
  RestirGiSettings s;
  s.unbiased = gi == frame::SurfaceGi::RestirUnbiased;
  if (gi == frame::SurfaceGi::PathTraced) {  // one fresh bounce sample per texel and frame, nothing reused
    s.temporal = false;
    s.fallback = false;
    s.spatial_neighbours = 0;
  }
  return s;
}

namespace {

// The options as read; unset ones take the backend's (the window's) defaults.
struct HtexOptions {
  std::optional<double> texels_per_unit;
  std::optional<uint32_t> pool_pages;
  uint32_t gi_frames = 1;  // frames of a still camera an offscreen GI image averages
  std::optional<uint32_t> gi_neighbours;
  std::optional<bool> gi_fallback;
};

HtexOptions read_options(const SurfaceOptions& o) {
  HtexOptions h;
  if (o.count("texels-per-unit")) h.texels_per_unit = option_number(o, "texels-per-unit", 0.0, true);
  if (o.count("pool-pages")) {
    h.pool_pages = option_uint(o, "pool-pages", 0);
    if (*h.pool_pages == 0) throw InputError(setting("pool-pages"), "the pool needs at least one page");
  }
  h.gi_frames = option_uint(o, "gi-frames", 1);
  if (h.gi_frames == 0) throw InputError(setting("gi-frames"), "at least one frame");
  if (o.count("gi-neighbours")) {
    h.gi_neighbours = option_uint(o, "gi-neighbours", 0);
    if (*h.gi_neighbours > 16) throw InputError(setting("gi-neighbours"), "at most 16 spatial neighbours");
  }
  if (o.count("gi-fallback")) h.gi_fallback = option_choice(o, "gi-fallback", "on", {"on", "off"}) == "on";
  return h;
}

class HtexBackend final : public SurfaceBackend {
 public:
  HtexBackend(SharedSurfaceScene& scene, const SurfaceOptions& options) : scene_(scene), options_(read_options(options)) {}

  void record(const BackendFrame& f) override {
    const vk::Device& device = scene_.device();
    if (!geometry_) {
      texels_per_unit_ = options_.texels_per_unit.value_or(htex_texels_per_unit(scene_.scene()));
      geometry_ = std::make_unique<HtexGeometry>(scene_.scene(), htex::LayoutOptions{.texels_per_unit = texels_per_unit_});
    }
    if (!targets_) targets_ = std::make_unique<HtexTargets>(create_htex_targets(device, f.extent));
    const VkAccelerationStructureKHR tlas = scene_.accel().tlas();
    if (f.gi == frame::SurfaceGi::None) {
      if (!plain_) {
        HtexSettings settings;
        settings.shadows = f.shadows;
        settings.pool_pages = options_.pool_pages.value_or(settings.pool_pages);
        plain_ = std::make_unique<HtexPass>(device, *geometry_, settings);
      }
      // The planner's rule (plan_shading_reuse): a still eye keeps every resident shadel's shading.
      last_reuse_ = reuse_.plan(f.camera, f.shadows);
      if (last_reuse_.invalidate) plain_->invalidate_shading();
      HtexSettings settings = plain_->settings();
      settings.reuse_shading = true;
      settings.shadows = f.shadows;
      settings.lod_bias = f.tuning.lod_bias.value_or(0.0f);
      plain_->set_settings(settings);
      plain_->record(f.cmd, scene_.gpu(), tlas, *targets_, f.camera, f.timer);
      reuse_.recorded(f.camera, f.shadows);
      last_ = plain_.get();
    } else {
      if (!gi_pass_) {
        HtexSettings settings;
        settings.shadows = f.shadows;
        settings.indirect = true;
        settings.sky_ambient = false;  // the sky arrives through GI's bounce rays, occluded
        settings.pool_pages = options_.pool_pages.value_or(kGiPoolPages);
        gi_pass_ = std::make_unique<HtexPass>(device, *geometry_, settings);
        gi_ = std::make_unique<HtexGi>(device, *gi_pass_, scene_.gpu(), scene_.accel());
      }
      if (gi_pass_->settings().shadows != f.shadows) {
        HtexSettings settings = gi_pass_->settings();
        settings.shadows = f.shadows;
        gi_pass_->set_settings(settings);
      }
      gi_pass_->record_marking(f.cmd, scene_.gpu(), tlas, *targets_, f.camera, f.timer);
      gi_pass_->record_allocation(f.cmd, *targets_, f.timer);
      gi_pass_->record_shading(f.cmd, *targets_, f.timer);
      if (f.indirect) {
        gi_settings_ = restir_gi_settings(f.gi);
        if (options_.gi_neighbours) gi_settings_.spatial_neighbours = *options_.gi_neighbours;
        if (options_.gi_fallback) gi_settings_.fallback = *options_.gi_fallback;
        gi_->record(f.cmd, f.camera, f.extent, gi_frame_++, gi_settings_, &f.timer);
      }
      gi_pass_->record_gather(f.cmd, *targets_, f.timer);
      last_ = gi_pass_.get();
      last_gi_ = f.gi;
    }
  }

  const vk::Image& display() const override { return targets_->color; }
  const vk::Image& depth() const override { return targets_->depth; }
  void release_targets() override { targets_.reset(); }
  void forget_shading() override { reuse_.forget(); }
  uint32_t gi_frames() const override { return gi_frame_; }
  void reset_gi() override {
    if (gi_) gi_->reset();
    gi_frame_ = 0;
  }
  uint32_t offscreen_frames(frame::SurfaceGi gi) const override { return gi == frame::SurfaceGi::None ? 1 : options_.gi_frames; }

  BackendCounts read_counts() const override {
    BackendCounts c;
    if (!last_) return c;
    const HtexCounters h = last_->read_counters();
    const bool gi = last_ == gi_pass_.get();
    c.shaded = h.shaded_texels;
    c.shaded_what = "texels";
    c.mode_bytes = h.pool_bytes + last_->tables().bytes + (gi ? gi_->reservoir_bytes() + gi_->persistent_bytes() : 0);
    c.detail = std::to_string(h.marked_shadels) + " shadels marked, " + std::to_string(h.resident_groups) + " groups resident, " +
               std::to_string(h.allocated_pages) + " pages allocated, " + std::to_string(h.released_pages) + " released" +
               (h.bias_levels ? ", bias " + std::to_string(h.bias_levels) + " levels" : "") + (h.overflow ? ", POOL OVERFLOW" : "");
    if (!gi)
      c.detail += "; " + std::to_string(h.reused_shadels) + " shadels reused, " + std::to_string(h.shaded_shadels) + " shaded (" +
                  last_reuse_.reason + ")";
    else
      c.detail += "; GI " + std::to_string(gi_frame_) + " frames";
    const htex::AtlasLayout& layout = geometry_->layout;
    const uint32_t pool_pages = last_->settings().pool_pages;
    c.space = "htex atlas " + std::to_string(layout.width()) + "x" + std::to_string(layout.height()) + " texels";
    c.summary.push_back("; marked " + std::to_string(h.marked_shadels) + " shadels in " + std::to_string(h.marked_groups) + " groups; shaded " +
                        std::to_string(h.shaded_texels) + " texels; pool " + std::to_string(pool_pages) + " pages (" +
                        std::to_string(h.pool_bytes) + " bytes)");
    if (gi)
      c.summary.push_back("GI " + std::string(frame::surface_gi_name(last_gi_)) + ": " + std::to_string(gi_frame_) + " frames averaged, " +
                          std::to_string(gi_settings_.spatial_neighbours) + " neighbours, fallback " + (gi_settings_.fallback ? "on" : "off") +
                          "; reservoirs " + std::to_string(gi_->reservoir_bytes()) + " bytes, persistent layer " +
                          std::to_string(gi_->persistent_bytes()) + " bytes");
    if (h.bias_levels > 0) c.summary.push_back("the pool was too small: level of detail biased by " + std::to_string(h.bias_levels));
    if (h.overflow)
      c.summary.push_back("the pool is too small even at the coarsest level: " + std::to_string(h.unallocated_groups) + " groups not shaded, " +
                          std::to_string(h.hole_pixels) + " pixels incomplete (raise " + setting("pool-pages") + " or lower " + setting("texels-per-unit") + ")");
    c.stats = {
        {"texels_per_unit", texels_per_unit_},
        {"atlas_width", uint64_t(layout.width())},
        {"atlas_height", uint64_t(layout.height())},
        {"htex_table_bytes", uint64_t(last_->tables().bytes)},
        {"pool_pages", uint64_t(pool_pages)},
        {"pool_bytes", uint64_t(h.pool_bytes)},
        {"marked_shadels", uint64_t(h.marked_shadels)},
        {"marked_groups", uint64_t(h.marked_groups)},
        {"marked_groups_unbiased", uint64_t(h.marked_groups_unbiased)},
        {"allocated_pages", uint64_t(h.allocated_pages)},
        {"resident_groups", uint64_t(h.resident_groups)},
        {"shaded_shadels", uint64_t(h.shaded_shadels)},
        {"shaded_texels", uint64_t(h.shaded_texels)},
        {"bias_levels", uint64_t(h.bias_levels)},
        {"overflow", h.overflow},
        {"unallocated_groups", uint64_t(h.unallocated_groups)},
        {"hole_pixels", uint64_t(h.hole_pixels)},
        {"gi", std::string(frame::surface_gi_name(gi ? last_gi_ : frame::SurfaceGi::None))},
    };
    if (gi) {
      c.stats.emplace_back("gi_frames", uint64_t(gi_frame_));
      c.stats.emplace_back("gi_neighbours", uint64_t(gi_settings_.spatial_neighbours));
      c.stats.emplace_back("gi_fallback", gi_settings_.fallback);
      c.stats.emplace_back("gi_reservoir_bytes", uint64_t(gi_->reservoir_bytes()));
      c.stats.emplace_back("gi_persistent_bytes", uint64_t(gi_->persistent_bytes()));
      c.stats.emplace_back("gi_persistent_texels", uint64_t(gi_->persistent_texels()));
    }
    return c;
  }

 private:
  SharedSurfaceScene& scene_;
  HtexOptions options_;
  std::unique_ptr<HtexGeometry> geometry_;
  double texels_per_unit_ = 0.0;  // the geometry's
  std::unique_ptr<HtexTargets> targets_;
  std::unique_ptr<HtexPass> plain_;    // the htex mode
  std::unique_ptr<HtexPass> gi_pass_;  // the GI modes: indirect buffer on, sky ambient off, its own pool
  std::unique_ptr<HtexGi> gi_;
  const HtexPass* last_ = nullptr;     // the last frame's pass
  frame::SurfaceGi last_gi_ = frame::SurfaceGi::None;
  RestirGiSettings gi_settings_;
  uint32_t gi_frame_ = 0;
  ReuseHistory reuse_;
  ShadingReuse last_reuse_;
};

SurfaceOptions command_options(SurfaceOptions o, frame::SurfaceGi gi) {
  if (gi == frame::SurfaceGi::None && (o.count("gi-frames") || o.count("gi-neighbours") || o.count("gi-fallback")))
    throw InputError(setting("gi"), setting("gi-frames") + ", " + setting("gi-neighbours") + " and " + setting("gi-fallback") + " need " +
                                        setting("gi", "biased|unbiased"));
  // render's own defaults: a fixed density (the window's follows the scene), and a pool for
  // render's default image size.
  o.emplace("texels-per-unit", "128");
  o.emplace("pool-pages", gi == frame::SurfaceGi::None ? "1024" : "64");
  if (gi != frame::SurfaceGi::None) o.emplace("gi-frames", "8");
  read_options(o);
  return o;
}

}  // namespace

const SurfaceBackendInfo& htex_backend() {
  static const SurfaceBackendInfo info{
      .name = "htex",
      .needs = "geometryShader, fragmentStoresAndAtomics, ray-tracing pipelines with indirect tracing",
      .passes =
          {
              .pre_z = {"pre-z + marking",
                        "a depth pre-pass, then once per visible pixel: its level of detail, and every shadel its footprint reads "
                        "marked in its group",
                        ""},
              .allocation = {"allocation", "marked shadel groups take pages of the pool (the level of detail biased while they do not fit), "
                                           "groups no longer marked release theirs; the task list of shadels to shade",
                             ""},
              .shading = {"shading", "the shading code at every texel of the task shadels (ray generation), into their pool pages", ""},
              .shadow_rays = {"shadow rays",
                              "one ray per point or directional light and " + std::to_string(PRISMOID_EMITTER_SHADOW_SAMPLES) +
                                  " per emissive triangle from each shaded texel",
                              ""},
              .gi = {{"gi samples", "each task texel's point, triangle and direction to the eye", ""},
                     {"gi initial+temporal", "a bounce ray per texel, merged with the texel's reservoir of the last frame", ""},
                     {"gi spatial", "reuse from neighbours walked over the surface; the indirect radiance per texel", ""}},
              .display = {"gather", "per pixel, its footprint's texels through the page table, blended across edges; the sky elsewhere", ""},
          },
      .options = {{"texels-per-unit", false, "D", "texel density (default 128; the window: 2048 along the scene's diagonal)"},
                  {"pool-pages", false, "N", "the texel pool's pages, 64 KiB each (default 1024; 64 with GI)"},
                  {"gi", false, "off|biased|unbiased|path-traced",
                   "one-bounce indirect light: the mode of this backend with that light"},
                  {"gi-frames", false, "N", "with GI: the image is the mean of N frames of the still camera (default 8)"},
                  {"gi-neighbours", false, "K", "with GI: spatial neighbours reused, 0..16 (default 4)"},
                  {"gi-fallback", false, "on|off", "with GI: the coarse layer after disocclusion (default on)"},
                  kShadowsOption},
      .tuning = kTuneLodBias,
      .device_problem = htex_device_problem,
      .command_options = command_options,
      .make = [](SharedSurfaceScene& scene, const SurfaceOptions& options) -> std::unique_ptr<SurfaceBackend> {
        return std::make_unique<HtexBackend>(scene, options);
      },
  };
  return info;
}

}  // namespace prismoid::surface
