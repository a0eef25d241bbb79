#include "app/viewer/reference_job.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "renderer/volume/cpu/reference_frame.hpp"

namespace prismoid::app {

FrameComparison compare_frames(const frame::OffscreenFrame& gpu, const frame::OffscreenFrame& ref, volume::Quantity quantity) {
  FrameComparison c;
  c.width = ref.width;
  c.height = ref.height;
  const bool per_pixel_quantity = quantity == volume::Quantity::OpticalDepth || quantity == volume::Quantity::Transmittance;
  if (per_pixel_quantity) {
    c.channels = quantity == volume::Quantity::OpticalDepth ? "optical depth" : "transmittance";
    if (quantity == volume::Quantity::OpticalDepth) {
      c.peak = 0.0;
      for (float v : ref.quantity)
        if (std::isfinite(v)) c.peak = std::max(c.peak, double(v));
    }
    c.error = reference::image_error(gpu.quantity, ref.quantity, c.peak);
  } else {
    c.channels = "display RGB";
    c.error = reference::image_error(gpu.display, ref.display, c.peak, 4, 3);
  }
  c.scale = c.error.max_abs;
  c.heat_map = per_pixel_quantity ? reference::error_heat_map(gpu.quantity, ref.quantity, 1, 1, c.scale)
                                  : reference::error_heat_map(gpu.display, ref.display, 4, 3, c.scale);
  return c;
}

ReferenceWorker::~ReferenceWorker() {
  if (thread_.joinable()) thread_.join();
}

void ReferenceWorker::start(ReferenceRequest request) {
  if (thread_.joinable()) thread_.join();  // a finished one nobody took
  done_.store(false, std::memory_order_release);
  running_key_ = request.key;
  started_ = std::chrono::steady_clock::now();
  thread_ = std::thread([this, r = std::move(request)] {
    ReferenceOutcome out;
    out.key = r.key;
    const auto start = std::chrono::steady_clock::now();
    try {
      const VkExtent2D size{r.gpu.width, r.gpu.height};
      const frame::OffscreenFrame ref = r.analytic_field ? frame::render_field_reference(*r.mesh, r.camera, r.resolve, size)
                                                         : frame::render_reference(*r.mesh, r.camera, r.resolve, size);
      out.reference_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      out.comparison = compare_frames(r.gpu, ref, r.resolve.quantity);
    } catch (const std::exception& e) {
      out.error = e.what();
    }
    outcome_ = std::move(out);
    done_.store(true, std::memory_order_release);
  });
}

double ReferenceWorker::seconds_running() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

std::optional<ReferenceOutcome> ReferenceWorker::take() {
  if (!thread_.joinable() || !done_.load(std::memory_order_acquire)) return std::nullopt;
  thread_.join();
  running_key_.clear();
  return std::move(outcome_);
}

}  // namespace prismoid::app
