#include "renderer/surface/surface_renderer.hpp"

#include <algorithm>
#include <stdexcept>

#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/memory.hpp"
#include "scene/input_error.hpp"
#include "scene/setting_names.hpp"

namespace prismoid::surface {

SurfaceRenderer::SurfaceRenderer(const vk::Device& device, const SurfaceScene& scene, SurfaceOptions options)
    : device_(device), shared_(device, scene), options_(std::move(options)), modes_(surface_modes(device)) {
  if (modes_.empty()) throw vk::NoSuitableDevice(device.capabilities().name + " can draw no surface mode (no geometryShader feature)");
  shadows_ = can_shadow() && shared_.contents().casts_shadows();
}

SurfaceRenderer::~SurfaceRenderer() = default;

bool SurfaceRenderer::can_shadow() const { return device_.ray_tracing_enabled(); }

void SurfaceRenderer::set_shadows(bool on) {
  if (on && !can_shadow())
    throw vk::NoSuitableDevice(device_.capabilities().name + " has no ray tracing (VK_KHR_ray_tracing_pipeline and "
                               "VK_KHR_acceleration_structure): shadows need it");
  shadows_ = on;
}

std::string SurfaceRenderer::mode_problem(const std::string& mode) const {
  if (std::find(modes_.begin(), modes_.end(), mode) != modes_.end()) return {};
  std::string known;
  for (const std::string& m : modes_) known += (known.empty() ? "" : ", ") + m;
  return "unknown surface mode " + mode + " (this device draws: " + known + ")";
}

const SurfaceMode& SurfaceRenderer::drawable(const std::string& mode) const {
  if (const std::string problem = mode_problem(mode); !problem.empty()) throw InputError(setting("mode", mode), problem);
  return *find_surface_mode(mode);
}

SurfaceBackend& SurfaceRenderer::backend(const SurfaceMode& mode) {
  std::unique_ptr<SurfaceBackend>& slot = backends_[mode.backend];
  if (!slot) slot = mode.backend->make(shared_, options_);
  return *slot;
}

void SurfaceRenderer::resize(VkExtent2D extent) {
  if (extent.width == 0 || extent.height == 0) throw InputError("surface image", "the image size must be positive");
  if (extent.width == extent_.width && extent.height == extent_.height) return;
  extent_ = extent;
  for (auto& [info, b] : backends_) b->release_targets();
  last_backend_ = nullptr;
}

frame::FramePlan SurfaceRenderer::plan(const std::string& mode) const {
  const SurfaceMode& m = drawable(mode);
  frame::SurfaceFrameSettings settings;
  settings.mode = std::string(m.name);
  settings.passes = m.backend->passes;
  settings.gi = m.gi;
  settings.shadows = shadows_;
  settings.device_traces_rays = can_shadow();
  return frame::plan_surface_frame(shared_.contents(), settings);
}

void SurfaceRenderer::record(VkCommandBuffer cmd, const Camera& camera, const std::string& mode, vk::GpuTimer& timer) {
  const SurfaceMode& m = drawable(mode);
  frame::FramePlan frame_plan = plan(mode);
  SurfaceBackend& b = backend(m);
  if (mode != last_mode_) b.forget_shading();  // another mode drew in between: shade afresh
  const BackendFrame frame{.cmd = cmd,
                           .camera = camera,
                           .extent = extent_,
                           .timer = timer,
                           .plan = frame_plan,
                           .gi = m.gi,
                           .shadows = frame_plan.find(frame::PassId::ShadowRays) != nullptr,
                           .indirect = frame_plan.find(frame::PassId::GlobalIllumination) != nullptr,
                           .tuning = tuning_,
                           .subpixel = subpixel_};
  const size_t first_timed = timer.recorded().size();
  b.record(frame);
  // The plan is the single source of truth: what was timed is exactly what was planned.
  const std::vector<std::string> timed(timer.recorded().begin() + std::ptrdiff_t(first_timed), timer.recorded().end());
  if (timed != frame_plan.gpu_pass_names()) {
    std::string got;
    for (const std::string& t : timed) got += (got.empty() ? "" : ", ") + t;
    throw std::logic_error("SurfaceRenderer: mode " + mode + " recorded passes (" + got + ") that differ from its plan");
  }
  last_mode_ = mode;
  last_backend_ = &b;
  last_plan_ = std::move(frame_plan);
}

const vk::Image& SurfaceRenderer::display() const {
  if (!last_backend_) throw std::logic_error("SurfaceRenderer::display before the first record");
  return last_backend_->display();
}

const vk::Image& SurfaceRenderer::depth() const {
  if (!last_backend_) throw std::logic_error("SurfaceRenderer::depth before the first record");
  return last_backend_->depth();
}

SurfaceRenderer::FrameCounts SurfaceRenderer::read_counts() const { return last_backend_ ? last_backend_->read_counts() : FrameCounts{}; }

SurfaceRenderer::Offscreen SurfaceRenderer::render_offscreen(const Camera& camera, const std::string& mode, VkExtent2D extent,
                                                             uint32_t supersample) {
  if (supersample == 0) throw InputError(setting("supersample"), "at least 1 sample per pixel side");
  const SurfaceMode& m = drawable(mode);
  resize(extent);
  const uint32_t k = supersample, still = backend(m).offscreen_frames(m.gi);
  const size_t pixels = size_t(extent.width) * extent.height;
  Offscreen out;
  out.width = extent.width;
  out.height = extent.height;
  std::vector<double> sum(pixels * 4, 0.0), alpha(pixels, 0.0);
  std::vector<float> rgba(pixels * 4);
  vk::GpuTimer timer(device_, 16);
  for (uint32_t j = 0; j < k; ++j)
    for (uint32_t i = 0; i < k; ++i) {
      subpixel_ = k == 1 ? glm::dvec2(0.0) : glm::dvec2((i + 0.5) / k - 0.5, (j + 0.5) / k - 0.5);
      for (uint32_t f = 0; f < still; ++f) {
        timer.submit_and_wait([&](VkCommandBuffer cmd) { record(cmd, camera, mode, timer); });
        vk::read_image(device_, display(), sizeof(float) * 4, std::as_writable_bytes(std::span(rgba)));
        for (size_t p = 0; p < rgba.size(); ++p) sum[p] += double(rgba[p]);
      }
      for (size_t p = 0; p < pixels; ++p) alpha[p] += double(rgba[4 * p + 3]);
      const std::vector<vk::PassTiming> passes = timer.read();
      FrameCounts counts = read_counts();
      if (out.passes.empty()) {
        out.passes = passes;
        out.counts = std::move(counts);
      } else {
        for (size_t p = 0; p < out.passes.size() && p < passes.size(); ++p) out.passes[p].gpu_ms += passes[p].gpu_ms;
        out.counts.shaded += counts.shaded;
      }
    }
  subpixel_ = glm::dvec2(0.0);
  out.rgba.resize(pixels * 4);
  const double positions = double(k) * double(k);
  for (size_t p = 0; p < sum.size(); ++p)
    out.rgba[p] = p % 4 == 3 ? static_cast<float>(alpha[p / 4] * (1.0 / positions)) : static_cast<float>(sum[p] * (1.0 / positions) / still);
  out.plan = last_plan_;
  return out;
}

uint32_t SurfaceRenderer::gi_frames() const { return last_backend_ ? last_backend_->gi_frames() : 0; }

void SurfaceRenderer::reset_gi() {
  for (auto& [info, b] : backends_) b->reset_gi();
}

void SurfaceRenderer::forget_shading() {
  for (auto& [info, b] : backends_) b->forget_shading();
}

void SurfaceRenderer::retune() {
  for (auto& [info, b] : backends_) b->retune(tuning_);
}

void SurfaceRenderer::set_shading_rate(float lod_bias, uint32_t block_budget) {
  tuning_.lod_bias = lod_bias;
  tuning_.block_budget = block_budget;
  retune();
}

void SurfaceRenderer::set_msa_amortization(uint32_t every_n_frames) {
  tuning_.amortize_every = every_n_frames;
  retune();
}

void SurfaceRenderer::set_msa_charts(msa::Parametrization charts) {
  const bool changed = charts != tuning_.msa_charts.value_or(msa::Parametrization::Projection);
  tuning_.msa_charts = charts;
  if (changed) retune();
}

msa::Parametrization SurfaceRenderer::msa_charts() const { return tuning_.msa_charts.value_or(msa::Parametrization::Projection); }

}  // namespace prismoid::surface
