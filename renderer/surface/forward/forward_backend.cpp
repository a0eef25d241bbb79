#include "renderer/surface/forward/forward_backend.hpp"

#include <memory>

#include "renderer/surface/forward/forward_pass.hpp"
#include "renderer/surface/forward/shadowed_forward_pass.hpp"
#include "renderer/vk/device.hpp"

namespace prismoid::surface {

namespace {

class ForwardBackend final : public SurfaceBackend {
 public:
  explicit ForwardBackend(SharedSurfaceScene& scene) : scene_(scene) {}

  void record(const BackendFrame& f) override {
    ForwardSettings settings;
    settings.subpixel = f.subpixel;
    if (f.shadows) {
      if (!shadowed_) shadowed_ = std::make_unique<ShadowedForwardPass>(scene_.device());
      if (!shadowed_targets_) shadowed_targets_ = std::make_unique<ShadowedForwardTargets>(create_shadowed_forward_targets(scene_.device(), f.extent));
      shadowed_->record(f.cmd, scene_.gpu(), scene_.accel(), *shadowed_targets_, f.camera, settings, f.timer);
      display_ = &shadowed_targets_->color;
      depth_ = &shadowed_targets_->depth;
      light_ = "direct light with ray-traced shadows (one shadow ray per point or directional light, " +
               std::to_string(PRISMOID_EMITTER_SHADOW_SAMPLES) + " per emissive triangle)";
    } else {
      if (!plain_) plain_ = std::make_unique<ForwardPass>(scene_.device());
      if (!plain_targets_) plain_targets_ = std::make_unique<ForwardTargets>(create_forward_targets(scene_.device(), f.extent));
      plain_->record(f.cmd, scene_.gpu(), *plain_targets_, f.camera, settings, f.timer);
      display_ = &plain_targets_->color;
      depth_ = &plain_targets_->depth;
      light_ = "direct light without shadows";
      for (const frame::SkippedPass& s : f.plan.skipped)
        if (s.name == "shadow rays") light_ += " (" + s.reason + ")";
    }
    shadows_ = f.shadows;
  }

  const vk::Image& display() const override { return *display_; }
  const vk::Image& depth() const override { return *depth_; }

  void release_targets() override {
    plain_targets_.reset();
    shadowed_targets_.reset();
  }

  BackendCounts read_counts() const override {
    BackendCounts c;
    c.shaded_what = "pixels";
    if (shadows_ && shadowed_) {
      c.shaded = shadowed_->read_shading_invocations();
      c.shaded_field = "shading_invocations";
    } else if (plain_) {
      c.shaded = plain_->read_fragment_invocations();
      if (plain_->counts_fragments()) c.shaded_field = "fragments";
    }
    c.summary = {"", light_};
    return c;
  }

 private:
  SharedSurfaceScene& scene_;
  std::unique_ptr<ForwardPass> plain_;
  std::unique_ptr<ForwardTargets> plain_targets_;
  std::unique_ptr<ShadowedForwardPass> shadowed_;
  std::unique_ptr<ShadowedForwardTargets> shadowed_targets_;
  const vk::Image* display_ = nullptr;
  const vk::Image* depth_ = nullptr;
  bool shadows_ = false;
  std::string light_;
};

std::string device_problem(const vk::Device& device) {
  if (!device.capabilities().geometry_shader)
    return device.capabilities().name + " has no geometryShader feature (fragment shaders cannot read gl_PrimitiveID)";
  return {};
}

}  // namespace

const SurfaceBackendInfo& forward_backend() {
  static const SurfaceBackendInfo info{
      .name = "forward",
      .needs = "geometryShader (gl_PrimitiveID in fragment shaders); ray-tracing pipelines for shadows",
      .passes =
          {
              .pre_z = {"depth pre-pass", "positions only, reversed-z depth, so that the shading pass runs once per covered pixel",
                        "positions and each pixel's nearest triangle (reversed-z depth), for the ray-traced shading"},
              .allocation = {"", "forward shades per pixel: no texture-space samples to allocate", ""},
              .shading = {"forward shading", "the shading code once per covered pixel (depth tested EQUAL), the sky elsewhere",
                          "one ray-generation invocation per pixel: the shading code at the pixel's point of its triangle, the sky elsewhere"},
              .shadow_rays = {"shadow rays",
                              "one ray per point or directional light and " + std::to_string(PRISMOID_EMITTER_SHADOW_SAMPLES) +
                                  " per emissive triangle from each shaded pixel, through the scene's TLAS",
                              ""},
              .gi = {},
              .display = {"", "forward shading writes the image itself", ""},
          },
      .options = {kShadowsOption,
                  {"supersample", false, "K", "the mean of K x K sub-pixel positions (default 1)"},
                  {"frames", false, "N", "timed frames, after 2 s of warm-up where N > 1 (default 1)"}},
      .device_problem = device_problem,
      .command_options = [](SurfaceOptions given, frame::SurfaceGi) { return given; },
      .make = [](SharedSurfaceScene& scene, const SurfaceOptions&) -> std::unique_ptr<SurfaceBackend> {
        return std::make_unique<ForwardBackend>(scene);
      },
  };
  return info;
}

}  // namespace prismoid::surface
