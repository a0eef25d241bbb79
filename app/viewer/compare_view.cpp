#include "app/viewer/compare_view.hpp"

#include <algorithm>

#include "app/viewer/compare.hpp"
#include "app/viewer/viewer_session.hpp"
#include "renderer/vk/device.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

// A vivid orange: seen against the white background and the dark medium alike.
constexpr VkClearColorValue kDividerColour{{1.0f, 0.45f, 0.0f, 1.0f}};

struct Rect {
  int32_t x0, y0, x1, y1;
};

void blit(VkCommandBuffer cmd, VkImage src, Rect from, VkImage dst, Rect to) {
  VkImageBlit region{};
  region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.srcOffsets[0] = {from.x0, from.y0, 0};
  region.srcOffsets[1] = {from.x1, from.y1, 1};
  region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.dstOffsets[0] = {to.x0, to.y0, 0};
  region.dstOffsets[1] = {to.x1, to.y1, 1};
  vkCmdBlitImage(cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region, VK_FILTER_NEAREST);
}

Rect whole(VkExtent2D e) { return {0, 0, int32_t(e.width), int32_t(e.height)}; }

}  // namespace

CompareView::CompareView(const vk::Device& device) : device_(device), b_timer_(device, 16) {}

CompareView::~CompareView() = default;

void CompareView::frame_finished() {
  if (!b_recorded_) return;
  status_.b_passes = b_timer_.read();
  b_recorded_ = false;
}

void CompareView::update(ViewerSession& s) {
  if (s.state.compare != CompareMode::Split && b_) {
    device_.wait_idle();
    b_.reset();
    b_mesh_.reset();
    status_.b_passes.clear();
  }
  if (s.state.compare == CompareMode::Split) update_split(s);
  if (s.state.compare == CompareMode::Difference) {
    update_difference(s);
  } else {
    status_.heat_map_shown = false;
    status_.computing = false;
    wanted_key_.clear();
    worker_.take();  // a finished reference nobody waits for
  }
}

void CompareView::update_split(ViewerSession& s) {
  const Dataset& d = s.state.dataset();
  // B at another time step, or the step A shows; a step of the mesh B draws sends its fields alone.
  const std::shared_ptr<const TetMesh>& mesh = s.state.compare_step_mesh ? s.state.compare_step_mesh : d.mesh;
  if (!b_ || b_mesh_ != mesh) {
    device_.wait_idle();
    if (!b_ || !b_->update_fields(*mesh)) {
      b_.reset();
      b_ = std::make_unique<frame::FrameRenderer>(device_, *mesh);
    }
    b_mesh_ = mesh;
  }
  b_->resize(s.swapchain.extent());
  b_settings_ = compare_frame_settings(s.state);
  status_.b_mode = s.state.compare_mode;
  if (s.state.compare_step && s.state.compare_step_mesh) status_.b_mode += ", step " + std::to_string(*s.state.compare_step);
  status_.b_quantity = b_settings_.resolve.quantity;
  try {
    b_->prepare(s.camera.camera(), b_settings_);
  } catch (const InputError& e) {  // B refused by this data or device: say so, stop comparing
    s.message(std::string("compare: ") + e.what());
    s.state.compare = CompareMode::Off;
  }
}

void CompareView::update_difference(ViewerSession& s) {
  const VkExtent2D size = reference_size(s.swapchain.extent(), kReferenceMaxSide);
  const std::string key = reference_key(s.camera.camera(), s.last_good, size, s.state.active);
  const auto now = std::chrono::steady_clock::now();
  if (key != wanted_key_) {
    wanted_key_ = key;
    changed_at_ = now;
  }
  if (auto out = worker_.take(); out && out->key == wanted_key_) {  // others are stale: dropped
    status_.reference_seconds = out->reference_seconds;
    if (out->comparison) {
      upload_heat_map(*out->comparison);
      out->comparison->heat_map.clear();
      s.report.comparisons.push_back(*out->comparison);
      status_.last = std::move(out->comparison);
      shown_key_ = out->key;
    } else {
      failed_key_ = out->key;
      status_.error = out->error;
      s.message("reference: " + out->error);
    }
  }
  status_.heat_map_shown = shown_key_ == wanted_key_;
  if (failed_key_ != wanted_key_) status_.error.clear();
  const bool due = !status_.heat_map_shown && failed_key_ != wanted_key_;
  const bool rested = std::chrono::duration<double>(now - changed_at_).count() >= kReferenceRestSeconds;
  if (due && rested && !worker_.busy()) {
    const Dataset& d = s.state.dataset();
    ReferenceRequest r;
    r.key = wanted_key_;
    r.mesh = d.mesh;
    r.analytic_field = d.field.has_value();  // as `render --mode reference`: the field is the truth
    r.camera = s.camera.camera();
    r.resolve = s.last_good.resolve;
    if (d.field) r.resolve.march.field = *d.field;
    try {
      device_.wait_idle();
      r.gpu = s.renderer.render_offscreen(r.camera, s.last_good, size);
      worker_.start(std::move(r));
    } catch (const InputError& e) {
      failed_key_ = wanted_key_;
      status_.error = e.what();
      s.message(std::string("reference: ") + e.what());
    }
  }
  status_.computing = due && status_.error.empty();
  status_.computing_seconds = worker_.busy() && worker_.running_key() == wanted_key_ ? worker_.seconds_running() : 0.0;
}

void CompareView::upload_heat_map(const FrameComparison& c) {
  device_.wait_idle();
  if (!heat_map_.get() || heat_map_.extent().width != c.width || heat_map_.extent().height != c.height)
    heat_map_ = vk::Image(device_, {c.width, c.height}, VK_FORMAT_R32G32B32A32_SFLOAT,
                          VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_SAMPLED_BIT);
  vk::Buffer staging(device_, c.heat_map.size() * sizeof(float), VK_BUFFER_USAGE_TRANSFER_SRC_BIT, vk::MemoryUse::HostVisible);
  staging.write(std::as_bytes(std::span(c.heat_map)));
  device_.submit_and_wait([&](VkCommandBuffer cmd) {
    vk::image_barrier(cmd, heat_map_.get(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {c.width, c.height, 1};
    vkCmdCopyBufferToImage(cmd, staging.get(), heat_map_.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    // Stays readable by the frames' blits.
    vk::image_barrier(cmd, heat_map_.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                      VK_ACCESS_2_TRANSFER_READ_BIT);
  });
}

void CompareView::record(VkCommandBuffer cmd, const ViewerSession& s) {
  if (s.state.compare != CompareMode::Split || !b_) return;
  b_timer_.reset(cmd);
  b_->record(cmd, s.camera.camera(), b_settings_, b_timer_);
  b_recorded_ = true;
}

void CompareView::present(VkCommandBuffer cmd, const ViewerSession& s, const vk::Image& a_display, VkImage target, VkExtent2D extent) {
  vk::image_barrier(cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  const VkExtent2D a = a_display.extent();
  if (s.state.compare == CompareMode::Split && b_recorded_) {
    // A's left half and B's right half, 1:1 (both rendered at the window's size), with a
    // two-pixel divider left where neither is copied.
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &kDividerColour, 1, &range);
    vk::image_barrier(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                      VK_ACCESS_2_TRANSFER_WRITE_BIT);
    const VkExtent2D b = b_->display().extent();
    const int32_t w = int32_t(std::min({extent.width, a.width, b.width})), h = int32_t(std::min({extent.height, a.height, b.height}));
    const int32_t half = w / 2;
    if (half > 1) blit(cmd, a_display.get(), {0, 0, half - 1, h}, target, {0, 0, half - 1, h});
    if (half + 1 < w) blit(cmd, b_->display().get(), {half + 1, 0, w, h}, target, {half + 1, 0, w, h});
  } else if (s.state.compare == CompareMode::Difference && status_.heat_map_shown && heat_map_.get()) {
    blit(cmd, heat_map_.get(), whole(heat_map_.extent()), target, whole(extent));
  } else {
    blit(cmd, a_display.get(), whole(a), target, whole(extent));
  }
}

}  // namespace prismoid::app
