#include "renderer/surface/texel/texel_backend.hpp"

#include <memory>

#include "renderer/surface/texel/texel_pass.hpp"
#include "renderer/vk/device.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

struct TexelOptions {
  texel::AtlasSettings atlas;
  float mip_bias = 0.0f;
};

TexelOptions read_options(const SurfaceOptions& o) {
  TexelOptions t;
  t.atlas.texels_per_unit = option_number(o, "texel-density", t.atlas.texels_per_unit, true);
  t.atlas.levels = option_uint(o, "texel-levels", t.atlas.levels);
  t.mip_bias = float(option_number(o, "mip-bias", 0.0, false));
  return t;
}

class TexelBackend final : public SurfaceBackend {
 public:
  TexelBackend(SharedSurfaceScene& scene, const SurfaceOptions& options) : scene_(scene), options_(read_options(options)) {}

  void record(const BackendFrame& f) override {
    const vk::Device& device = scene_.device();
    if (!pass_) {
      atlas_ = std::make_unique<texel::TexelAtlas>(build_texel_atlas_for(device, scene_.scene(), options_.atlas));
      TexelSettings settings;
      settings.shadows = f.shadows;
      pass_ = std::make_unique<TexelPass>(device, *atlas_, settings);
    }
    if (!targets_) targets_ = std::make_unique<TexelTargets>(create_texel_targets(device, f.extent));
    TexelSettings settings = pass_->settings();
    settings.shadows = f.shadows;
    settings.lod_bias = f.tuning.lod_bias.value_or(options_.mip_bias);
    // The planner's rule (plan_shading_reuse): a still eye reuses every tile shaded since the last
    // change, whatever its age; a moved eye shades again.
    last_reuse_ = reuse_.plan(f.camera, f.shadows);
    settings.max_age = last_reuse_.invalidate ? 1u : 0xffffffffu;
    pass_->set_settings(settings);
    if (last_reuse_.invalidate) pass_->invalidate_shading();
    pass_->record(f.cmd, scene_.gpu(), scene_.accel().tlas(), *targets_, f.camera, f.timer);
    reuse_.recorded(f.camera, f.shadows);
  }

  const vk::Image& display() const override { return targets_->color; }
  const vk::Image& depth() const override { return targets_->depth; }
  void release_targets() override { targets_.reset(); }
  void forget_shading() override { reuse_.forget(); }

  BackendCounts read_counts() const override {
    BackendCounts c;
    if (!pass_) return c;
    const TexelCounters t = pass_->read_counters();
    const texel::TexelAtlas& atlas = *atlas_;
    c.shaded = t.shaded_texels;
    c.shaded_what = "texels";
    c.mode_bytes = t.atlas_bytes;
    c.detail = std::to_string(t.queued_tiles) + " tiles shaded (" + last_reuse_.reason + "); atlas " + std::to_string(atlas.width) + " x " +
               std::to_string(atlas.height) + ", " + std::to_string(atlas.levels) + " levels, " + std::to_string(atlas.charts.size()) +
               " charts" + (t.hole_pixels ? ", HOLES " + std::to_string(t.hole_pixels) : "");
    c.space = "texel atlas " + std::to_string(atlas.width) + "x" + std::to_string(atlas.height) + " texels, " + std::to_string(atlas.levels) +
              " levels, " + std::to_string(atlas.charts.size()) + " charts";
    c.summary.push_back("; queued " + std::to_string(t.queued_tiles) + " tiles; shaded " + std::to_string(t.shaded_texels) +
                        " texels; atlas memory " + std::to_string(t.atlas_bytes) + " bytes" +
                        (t.hole_pixels ? "; " + std::to_string(t.hole_pixels) + " pixels read a texel never shaded" : ""));
    c.stats = {
        {"texels_per_unit", atlas.texels_per_unit},
        {"atlas_width", uint64_t(atlas.width)},
        {"atlas_height", uint64_t(atlas.height)},
        {"levels", uint64_t(atlas.levels)},
        {"charts", uint64_t(atlas.charts.size())},
        {"mip_bias", double(pass_->settings().lod_bias)},
        {"queued_tiles", uint64_t(t.queued_tiles)},
        {"shaded_texels", uint64_t(t.shaded_texels)},
        {"hole_pixels", uint64_t(t.hole_pixels)},
        {"atlas_bytes", uint64_t(t.atlas_bytes)},
    };
    return c;
  }

 private:
  SharedSurfaceScene& scene_;
  TexelOptions options_;
  std::unique_ptr<texel::TexelAtlas> atlas_;
  std::unique_ptr<TexelPass> pass_;
  std::unique_ptr<TexelTargets> targets_;
  ReuseHistory reuse_;
  ShadingReuse last_reuse_;
};

}  // namespace

const SurfaceBackendInfo& texel_backend() {
  static const SurfaceBackendInfo info{
      .name = "texel",
      .needs = "geometryShader, fragmentStoresAndAtomics, ray-tracing pipelines with indirect tracing",
      .passes =
          {
              .pre_z = {"pre-z + queue",
                        "a depth pre-pass, then once per visible pixel: its level, and the 8x8 tiles its four bilinear taps read "
                        "queued where their shading is older than the age threshold",
                        ""},
              .allocation = {"", "the texel atlas is static: every texel has its place from the start", ""},
              .shading = {"shading", "the shading code at every texel of the queued tiles (ray generation), into the atlas", ""},
              .shadow_rays = {"shadow rays",
                              "one ray per point or directional light and " + std::to_string(PRISMOID_EMITTER_SHADOW_SAMPLES) +
                                  " per emissive triangle from each shaded texel",
                              ""},
              .gi = {},
              .display = {"gather", "per pixel, its four taps blended bilinearly from the atlas; the sky elsewhere", ""},
          },
      .options = {{"texel-density", false, "D",
                   "level-0 texels per unit (default: about 4M texels in all, fewer where the device's buffers are smaller)"},
                  {"texel-levels", false, "N", "mip levels (default 4)"},
                  {"mip-bias", false, "B", "shading rate: +1 shades a quarter (default 0)"},
                  kShadowsOption},
      .tuning = kTuneLodBias,
      .device_problem = texel_device_problem,
      .command_options = [](SurfaceOptions given, frame::SurfaceGi) {
        read_options(given);
        return given;
      },
      .make = [](SharedSurfaceScene& scene, const SurfaceOptions& options) -> std::unique_ptr<SurfaceBackend> {
        return std::make_unique<TexelBackend>(scene, options);
      },
  };
  return info;
}

}  // namespace prismoid::surface
