#pragma once
// The difference view's slow half: the CPU double-precision reference of one view, computed on
// a worker thread while the window keeps drawing, then compared with the GPU frame of the same
// camera, settings and size (image_error and error_heat_map of renderer/reference).
//
// The references cannot be interrupted, so the worker is never abandoned: a result that no
// longer matches the view is dropped when it arrives, at most one reference is computed at a
// time, and closing the window waits for the one running (the reduced size bounds how long).
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/metrics/image_error.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh_fwd.hpp"

namespace prismoid::app {

// A frame against its reference: which channels, the statistics, and the heat map (linear
// RGBA, `scale` at white).
struct FrameComparison {
  std::string channels;  // what was compared: "optical depth", "transmittance", "display RGB"
  reference::ImageError error;
  double peak = 1.0;     // the PSNR's peak
  double scale = 0.0;    // the heat map's white: the largest error
  std::vector<float> heat_map;
  uint32_t width = 0, height = 0;
};

// Compares the channels that carry the quantity: the quantity image for optical depth (peak:
// the reference's largest value) and transmittance (peak 1), display RGB for colour and
// isosurfaces (peak 1).
FrameComparison compare_frames(const frame::OffscreenFrame& gpu, const frame::OffscreenFrame& reference, volume::Quantity quantity);

struct ReferenceRequest {
  std::string key;                          // reference_key of the view it is for
  std::shared_ptr<const TetMesh> mesh;
  bool analytic_field = false;              // the field in settings.resolve.march is the truth
  Camera camera;
  volume::ResolveSettings resolve;
  frame::OffscreenFrame gpu;                // the GPU frame of that view, at the reference's size
};

struct ReferenceOutcome {
  std::string key;
  std::optional<FrameComparison> comparison;
  std::string error;           // why there is none (the reference refused the data)
  double reference_seconds = 0.0;
};

class ReferenceWorker {
 public:
  ReferenceWorker() = default;
  ~ReferenceWorker();  // waits for a running reference
  ReferenceWorker(const ReferenceWorker&) = delete;
  ReferenceWorker& operator=(const ReferenceWorker&) = delete;

  // Starts computing on a new thread; only when !busy().
  void start(ReferenceRequest request);
  bool busy() const { return thread_.joinable() && !done_.load(std::memory_order_acquire); }
  // The key being computed, and for how long.
  const std::string& running_key() const { return running_key_; }
  double seconds_running() const;
  // The finished outcome, once (joins the finished thread).
  std::optional<ReferenceOutcome> take();

 private:
  std::thread thread_;
  std::atomic<bool> done_{false};
  ReferenceOutcome outcome_;  // written by the thread before done_
  std::string running_key_;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace prismoid::app
