#include "renderer/surface/msa/msa_backend.hpp"

#include <algorithm>
#include <memory>
#include <sstream>

#include "renderer/surface/msa/msa_pass.hpp"
#include "renderer/vk/device.hpp"
#include "scene/setting_names.hpp"
#include "shaders/shared/surface.h"

namespace prismoid::surface {

namespace {

struct MsaOptions {
  msa::Clustering clustering = msa::Clustering::NormalCone;
  msa::Parametrization charts = msa::Parametrization::Projection;
  std::optional<uint32_t> superblocks;
  uint32_t budget = 0;
};

MsaOptions read_options(const SurfaceOptions& o) {
  MsaOptions m;
  m.clustering = option_choice(o, "meshlets", "normal-cone", {"normal-cone", "meshoptimizer"}) == "meshoptimizer" ? msa::Clustering::Meshoptimizer
                                                                                                                  : msa::Clustering::NormalCone;
  msa::parse_parametrization(option_choice(o, "msa-charts", "projection", {"projection", "conformal", "perspective", "orthographic"}),
                             m.charts);
  if (o.count("msa-superblocks")) m.superblocks = option_uint(o, "msa-superblocks", 0);
  m.budget = option_uint(o, "shading-budget", 0);
  return m;
}

bool same_view(const Camera& a, const Camera& b, VkExtent2D ea, VkExtent2D eb) { return a == b && ea.width == eb.width && ea.height == eb.height; }

class MsaBackend final : public SurfaceBackend {
 public:
  MsaBackend(SharedSurfaceScene& scene, const SurfaceOptions& options) : scene_(scene), options_(read_options(options)) {}

  void record(const BackendFrame& f) override {
    const vk::Device& device = scene_.device();
    const msa::Parametrization charts = f.tuning.msa_charts.value_or(options_.charts);
    if (!pass_) {
      meshlets_ = std::make_unique<msa::MeshletSet>(msa::build_meshlets(scene_.scene(), {.clustering = options_.clustering, .parametrization = charts}));
      charts_ = charts;
      MsaSettings settings;
      settings.shadows = f.shadows;
      // As many superblocks (1 MiB each) as one storage buffer holds, up to 256 (16 M texels).
      settings.superblocks = options_.superblocks.value_or(
          uint32_t(std::clamp<uint64_t>(device.capabilities().max_storage_buffer_range / (uint64_t(256) * 256 * 16), 1, 256)));
      pass_ = std::make_unique<MsaPass>(device, *meshlets_, settings);
    }
    if (!targets_) targets_ = std::make_unique<MsaTargets>(create_msa_targets(device, f.extent));
    MsaSettings settings = pass_->settings();
    settings.shadows = f.shadows;
    settings.budget_texels = f.tuning.block_budget.value_or(options_.budget);
    // Per-frame charts (MSA-P, MSA-O) change with any change of the view, so a block's texels keep
    // their meaning only while the camera stays exactly where it was: no amortization over them.
    const bool frame_charts = msa::per_frame(charts_);
    settings.shade_every = frame_charts ? 0u : f.tuning.amortize_every;
    settings.frame_charts = charts_;
    pass_->set_settings(settings);
    // The planner's rule: a still eye reuses every block's shading; a moved eye shades them again,
    // unless amortized (then only the first frame and changed settings do, and shade_every).
    last_reuse_ = reuse_.plan(f.camera, f.shadows, settings.shade_every > 0);
    if (frame_charts && !last_reuse_.invalidate && last_camera_ && !same_view(*last_camera_, f.camera, last_extent_, f.extent)) {
      last_reuse_.invalidate = true;
      last_reuse_.reason = "the view changed: per-frame charts are made anew";
    }
    if (last_reuse_.invalidate) pass_->invalidate_shading();
    last_camera_ = f.camera;
    last_extent_ = f.extent;
    pass_->record(f.cmd, scene_.gpu(), scene_.accel().tlas(), *targets_, f.camera, f.timer);
    reuse_.recorded(f.camera, f.shadows);
  }

  const vk::Image& display() const override { return targets_->color; }
  const vk::Image& depth() const override { return targets_->depth; }
  void release_targets() override { targets_.reset(); }
  void forget_shading() override { reuse_.forget(); }
  void retune(const SurfaceTuning& tuning) override {
    reuse_.forget();
    if (pass_ && tuning.msa_charts.value_or(options_.charts) != charts_) {  // rebuilt with the new charts at the next frame
      pass_.reset();
      meshlets_.reset();
    }
  }

  BackendCounts read_counts() const override {
    BackendCounts c;
    if (!pass_) return c;
    const MsaCounters m = pass_->read_counters();
    const MsaSettings& settings = pass_->settings();
    c.shaded = m.shaded_texels;
    c.shaded_what = "texels";
    c.mode_bytes = m.atlas_bytes;
    c.detail = std::to_string(m.seen_meshlets) + " of " + std::to_string(meshlets_->meshlets.size()) + " meshlets seen, " +
               std::to_string(m.shaded_blocks) + " blocks shaded (" + last_reuse_.reason + "), " + std::to_string(m.allocated_blocks) +
               " allocated, " + std::to_string(m.released_blocks) + " released; " + std::to_string(m.free_superblocks) + " superblocks free" +
               (m.hole_pixels ? ", ATLAS FULL: " + std::to_string(m.hole_pixels) + " pixels unshaded" : "");
    c.space = "meshlet atlas " + std::to_string(pass_->atlas_width()) + "x" + std::to_string(pass_->atlas_height()) + " texels, " +
              std::to_string(meshlets_->meshlets.size()) + " meshlets";
    std::string factor;
    if (m.budget_factor < 1.0f) {
      std::ostringstream f;
      f.precision(9);
      f << m.budget_factor;
      factor = ", budget factor " + f.str();
    }
    c.summary.push_back("; " + std::to_string(m.seen_meshlets) + " meshlets seen, " + std::to_string(m.allocated_blocks) + " blocks allocated (" +
                        std::to_string(m.held_texels) + " texels" + factor + "); shaded " + std::to_string(m.shaded_texels) + " texels in " +
                        std::to_string(m.shaded_tiles) + " tiles; atlas memory " + std::to_string(m.atlas_bytes) + " bytes" +
                        (m.hole_pixels ? "; " + std::to_string(m.hole_pixels) + " pixels without shading (atlas too small: raise " + setting("msa-superblocks") + ")"
                                       : ""));
    c.stats = {
        {"meshlets", uint64_t(meshlets_->meshlets.size())},
        {"clustering", std::string(options_.clustering == msa::Clustering::Meshoptimizer ? "meshoptimizer" : "normal-cone")},
        {"charts", std::string(msa::parametrization_name(charts_))},
        {"conformal_fallbacks", uint64_t(meshlets_->conformal_fallbacks)},
        {"superblocks", uint64_t(settings.superblocks)},
        {"shading_budget", uint64_t(settings.budget_texels)},
        {"budget_factor", double(m.budget_factor)},
        {"stretch_l2", m.stretch_l2},
        {"stretch_linf", m.stretch_linf},
        {"seen_meshlets", uint64_t(m.seen_meshlets)},
        {"allocated_blocks", uint64_t(m.allocated_blocks)},
        {"block_texels", uint64_t(m.held_texels)},
        {"shaded_tiles", uint64_t(m.shaded_tiles)},
        {"shaded_texels", uint64_t(m.shaded_texels)},
        {"hole_pixels", uint64_t(m.hole_pixels)},
        {"atlas_bytes", uint64_t(m.atlas_bytes)},
    };
    return c;
  }

 private:
  SharedSurfaceScene& scene_;
  MsaOptions options_;
  std::unique_ptr<msa::MeshletSet> meshlets_;
  msa::Parametrization charts_ = msa::Parametrization::Projection;  // meshlets_'s charts
  std::optional<Camera> last_camera_;
  VkExtent2D last_extent_{};
  std::unique_ptr<MsaPass> pass_;
  std::unique_ptr<MsaTargets> targets_;
  ReuseHistory reuse_;
  ShadingReuse last_reuse_;
};

}  // namespace

const SurfaceBackendInfo& msa_backend() {
  static const SurfaceBackendInfo info{
      .name = "msa",
      .needs = "geometryShader, fragmentStoresAndAtomics, ray-tracing pipelines with indirect tracing",
      .passes =
          {
              .pre_z = {"pre-z + visibility",
                        "a depth pre-pass, then once per visible pixel: its meshlet marked seen with the texel density it asks for", ""},
              .allocation = {"block management",
                             "each seen meshlet's block sized from its pixels (and the budget), blocks no longer seen or resized released, "
                             "new blocks allocated in superblocks, the tiles of blocks to shade queued",
                             ""},
              .shading = {"shading", "the shading code at every texel of the queued tiles (ray generation), into the atlas", ""},
              .shadow_rays = {"shadow rays",
                              "one ray per point or directional light and " + std::to_string(PRISMOID_EMITTER_SHADOW_SAMPLES) +
                                  " per emissive triangle from each shaded texel",
                              ""},
              .gi = {},
              .display = {"display", "per pixel, its chart point through its meshlet's block, bilinear from the atlas; the sky elsewhere", ""},
          },
      .options = {{"meshlets", false, "normal-cone|meshoptimizer", "how triangles are grouped into meshlets (default normal-cone)"},
                  {"msa-charts", false, "projection|conformal|perspective|orthographic",
                   "the meshlets' charts: static orthogonal projection (default) or least-squares conformal maps (the "
                   "paper's LSCM); or made every frame from the camera: perspective (MSA-P) or orthographic (MSA-O)"},
                  {"msa-superblocks", false, "N", "the atlas's superblocks, 256x256 texels each (default 64)"},
                  {"shading-budget", false, "TEXELS", "block texels shaded per frame (default: no budget)"},
                  kShadowsOption},
      .tuning = kTuneBlockBudget | kTuneAmortize | kTuneCharts,
      .device_problem = msa_device_problem,
      .command_options = [](SurfaceOptions given, frame::SurfaceGi) {
        given.emplace("msa-superblocks", "64");
        read_options(given);
        return given;
      },
      .make = [](SharedSurfaceScene& scene, const SurfaceOptions& options) -> std::unique_ptr<SurfaceBackend> {
        return std::make_unique<MsaBackend>(scene, options);
      },
  };
  return info;
}

}  // namespace prismoid::surface
