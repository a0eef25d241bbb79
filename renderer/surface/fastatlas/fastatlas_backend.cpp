#include "renderer/surface/fastatlas/fastatlas_backend.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "renderer/surface/fastatlas/fastatlas_pass.hpp"
#include "renderer/vk/device.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

FastAtlasSettings read_options(const SurfaceOptions& o) {
  FastAtlasSettings s;
  const uint32_t side = option_uint(o, "atlas", s.atlas_width);
  if (side < 64 || side > 16384 || (side & (side - 1)) != 0)
    throw InputError(setting("atlas"), "the atlas side must be a power of two from 64 to 16384 texels (got " + std::to_string(side) + ")");
  s.atlas_width = s.atlas_height = side;
  s.shading_scale = option_number(o, "shading-scale", 1.0, true);
  if (s.shading_scale > 4.0) throw InputError(setting("shading-scale"), "at most 4 (16 texels per pixel)");
  s.refresh = option_uint(o, "atlas-refresh", 0);
  if (s.refresh > 1000) throw InputError(setting("atlas-refresh"), "at most 1000 frames between refreshes");
  return s;
}

std::string percent(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", 100.0 * x);
  return b;
}

class FastAtlasBackend final : public SurfaceBackend {
 public:
  FastAtlasBackend(SharedSurfaceScene& scene, const SurfaceOptions& options) : scene_(scene), options_(read_options(options)) {}

  void record(const BackendFrame& f) override {
    const vk::Device& device = scene_.device();
    if (!pass_) pass_ = std::make_unique<FastAtlasPass>(device, scene_.scene(), options_);
    if (!targets_) targets_ = std::make_unique<TextureSpaceTargets>(create_texture_space_targets(device, f.extent));
    FastAtlasSettings s = options_;
    s.shadows = f.shadows;
    // The shading-rate control (SF, section 6 of the paper): the window's and the bench's level-
    // of-detail bias halves the texels per side for each +1.
    if (f.tuning.lod_bias) s.shading_scale = std::min(4.0, options_.shading_scale * std::exp2(-double(*f.tuning.lod_bias)));
    // The planner's rule (plan_shading_reuse) keeps shading while the eye stays; but the atlas
    // is made from the whole view, so only the same view (and settings) gives the same atlas bit
    // for bit and keeps its shading; a turned camera shades again.
    last_reuse_ = reuse_.plan(f.camera, f.shadows);
    const FastAtlasSettings& now = pass_->settings();
    const bool same_view = last_camera_ == f.camera && extent_.width == f.extent.width && extent_.height == f.extent.height;
    if (!last_reuse_.invalidate && !same_view) {
      last_reuse_.invalidate = true;
      last_reuse_.reason = "the view changed: a new atlas";
    }
    s.reuse = !last_reuse_.invalidate && now.shading_scale == s.shading_scale && now.atlas_width == s.atlas_width &&
              now.atlas_height == s.atlas_height;
    pass_->set_settings(s);
    pass_->record(f.cmd, scene_.gpu(), scene_.accel().tlas(), *targets_, f.camera, f.timer);
    reuse_.recorded(f.camera, f.shadows);
    last_camera_ = f.camera;
    extent_ = f.extent;
  }

  const vk::Image& display() const override { return targets_->color; }
  const vk::Image& depth() const override { return targets_->depth; }
  void release_targets() override {
    targets_.reset();
    reuse_.forget();
  }
  void forget_shading() override {
    reuse_.forget();
    if (pass_) pass_->forget_last_frame();
  }

  BackendCounts read_counts() const override {
    BackendCounts c;
    if (!pass_) return c;
    const FastAtlasCounters t = pass_->read_counters();
    const FastAtlasSettings& s = pass_->settings();
    const double texels = double(s.atlas_width) * s.atlas_height;
    c.shaded = t.shaded_texels;
    c.shaded_what = "texels";
    c.mode_bytes = t.atlas_bytes;
    const std::string size = std::to_string(s.atlas_width) + "x" + std::to_string(s.atlas_height);
    const std::string scale = t.fits ? "scale " + std::to_string(t.scale).substr(0, 6) + " (candidate " + std::to_string(t.candidate) + " of 64)"
                                     : "NO CANDIDATE SCALE FITS";
    c.detail = std::to_string(t.charts) + " charts, " + scale + ", " + std::to_string(t.rows_used) + " of " + std::to_string(s.atlas_height) +
               " rows; " + std::to_string(t.shaded_texels) + " texels shaded (" + last_reuse_.reason + ")" +
               (t.hole_pixels ? ", HOLES " + std::to_string(t.hole_pixels) : "");
    c.space = "fastatlas atlas " + size + " texels, " + std::to_string(t.charts) + " charts, " + scale;
    if (t.temporal) c.detail += "; " + std::to_string(t.reused_texels) + " texels from the last frame";
    c.summary.push_back("; " + std::to_string(t.charts) + " charts of " + std::to_string(t.visible_triangles) + " visible triangles; " + scale +
                        "; " + std::to_string(t.rows_used) + " atlas rows used; shaded " + std::to_string(t.shaded_texels) + " texels (" +
                        percent(t.shaded_texels / texels) + " % of the atlas), " + std::to_string(t.border_texels) + " of them border" +
                        (t.hole_pixels ? "; " + std::to_string(t.hole_pixels) + " pixels found no texel" : ""));
    c.stats = {
        {"atlas_width", uint64_t(s.atlas_width)},
        {"atlas_height", uint64_t(s.atlas_height)},
        {"shading_scale_target", s.shading_scale},
        {"charts", uint64_t(t.charts)},
        {"visible_triangles", uint64_t(t.visible_triangles)},
        {"fits", t.fits},
        {"candidate", uint64_t(t.candidate)},
        {"scale", t.scale},
        {"stretch_l2", t.stretch_l2},
        {"stretch_linf", t.stretch_linf},
        {"rows_used", uint64_t(t.rows_used)},
        {"shaded_texels", uint64_t(t.shaded_texels)},
        {"border_texels", uint64_t(t.border_texels)},
        {"atlas_fill", t.shaded_texels / texels},
        {"hole_pixels", uint64_t(t.hole_pixels)},
        {"atlas_bytes", t.atlas_bytes},
        {"reused", pass_->settings().reuse},
        {"atlas_refresh", uint64_t(s.refresh)},
        {"temporal", t.temporal},
        {"reused_texels", uint64_t(t.reused_texels)},
    };
    for (const vk::PassTiming& p : pass_->atlas_timings()) c.stats.emplace_back("atlasing_" + p.name + "_ms", p.gpu_ms);
    return c;
  }

 private:
  SharedSurfaceScene& scene_;
  FastAtlasSettings options_;
  std::unique_ptr<FastAtlasPass> pass_;
  std::unique_ptr<TextureSpaceTargets> targets_;
  VkExtent2D extent_{};
  std::optional<Camera> last_camera_;
  ReuseHistory reuse_;
  ShadingReuse last_reuse_;
};

}  // namespace

const SurfaceBackendInfo& fastatlas_backend() {
  static const SurfaceBackendInfo info{
      .name = "fastatlas",
      .needs = "geometryShader, fragmentStoresAndAtomics, ray-tracing pipelines with indirect tracing",
      .passes =
          {
              .pre_z = {"pre-z + visibility",
                        "a depth pre-pass, then once per visible pixel: its triangle marked visible (one entry per triangle) and its "
                        "weights kept for the lookup",
                        ""},
              .allocation = {"atlasing",
                             "a new atlas of what is visible: charts (union-find over shared edges and vertices), their screen boxes "
                             "(clipped at the near plane), a deterministic order, packing at 64 candidate scales, the triangle-ID "
                             "atlas and its borders",
                             ""},
              .shading = {"shading", "the shading code at every atlas texel holding a triangle (ray generation), into the atlas", ""},
              .shadow_rays = {"shadow rays",
                              "one ray per point or directional light and " + std::to_string(PRISMOID_EMITTER_SHADOW_SAMPLES) +
                                  " per emissive triangle from each shaded texel",
                              ""},
              .gi = {},
              .display = {"lookup", "per pixel, its chart's map into the atlas and the hard-edge filter over four taps; the sky elsewhere", ""},
          },
      .options = {{"atlas", false, "N", "the atlas side in texels, a power of two (default 4096)"},
                  {"shading-scale", false, "SF",
                   "texels per pixel side at the largest candidate scale: 0.5 shades a quarter (default 1)"},
                  {"atlas-refresh", false, "N",
                   "temporal reuse while the camera moves: shade everything every N-th frame and take the last "
                   "frame's shading where it holds the same surface point in between (default 0: off)"},
                  kShadowsOption},
      .tuning = kTuneLodBias,
      .device_problem = fastatlas_device_problem,
      .command_options = [](SurfaceOptions given, frame::SurfaceGi) {
        read_options(given);
        return given;
      },
      .make = [](SharedSurfaceScene& scene, const SurfaceOptions& options) -> std::unique_ptr<SurfaceBackend> {
        return std::make_unique<FastAtlasBackend>(scene, options);
      },
  };
  return info;
}

}  // namespace prismoid::surface
