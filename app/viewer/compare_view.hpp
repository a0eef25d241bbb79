#pragma once
// The window's compare modes on the GPU side. Split: a second FrameRenderer draws mode B on the
// same camera at full size, and the swapchain image gets A's left half and B's right half with
// a divider between. Difference: the current mode's GPU frame at the reference's size is
// compared with the CPU reference (ReferenceWorker, off the window's thread), and the heat map
// is uploaded to an image and stretched over the view while it matches the view.
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/reference_job.hpp"
#include "renderer/frame/frame_renderer.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/timer.hpp"

namespace prismoid::app {

struct ViewerSession;

// The reference's long side at most: a 512 x 320 reference is a few seconds on the CPU.
inline constexpr uint32_t kReferenceMaxSide = 512;
// The camera must rest this long before a new reference starts (a drag would start dozens).
inline constexpr double kReferenceRestSeconds = 0.3;

// What the HUD and the report show about the comparison.
struct CompareStatus {
  // Split: B's label and the last finished frame's passes.
  std::string b_mode;
  volume::Quantity b_quantity{};
  std::vector<vk::PassTiming> b_passes;
  // Difference.
  bool computing = false;       // a reference for the current view is being computed
  double computing_seconds = 0.0;
  bool heat_map_shown = false;  // the last comparison matches the view and is drawn
  std::optional<FrameComparison> last;  // the last comparison (statistics; heat map dropped)
  double reference_seconds = 0.0;
  std::string error;            // the reference refused the view
};

class CompareView {
 public:
  explicit CompareView(const vk::Device& device);
  ~CompareView();

  // After the previous frame's fence: B's timings.
  void frame_finished();
  // Before recording a frame (no frame in flight): B prepared, or the reference collected,
  // uploaded, or started when the view has rested.
  void update(ViewerSession& s);
  // B's passes (split only), after A's.
  void record(VkCommandBuffer cmd, const ViewerSession& s);
  // The view into the swapchain image: A's display, A | B, or the heat map. Leaves the image
  // in TRANSFER_DST for the UI pass, as the plain blit does.
  void present(VkCommandBuffer cmd, const ViewerSession& s, const vk::Image& a_display, VkImage target, VkExtent2D extent);

  // Whether the difference view shows the reference of the current view, or gave up on it.
  bool reference_settled() const { return status_.heat_map_shown || !status_.error.empty(); }
  const CompareStatus& status() const { return status_; }

 private:
  void update_split(ViewerSession& s);
  void update_difference(ViewerSession& s);
  void upload_heat_map(const FrameComparison& c);

  const vk::Device& device_;
  CompareStatus status_;
  // Split.
  std::unique_ptr<frame::FrameRenderer> b_;
  std::shared_ptr<const TetMesh> b_mesh_;  // the dataset B was made for (held: a freed mesh's address could be the next one's)
  vk::GpuTimer b_timer_;
  bool b_recorded_ = false;
  frame::FrameSettings b_settings_;
  // Difference.
  ReferenceWorker worker_;
  std::string wanted_key_;   // the current view's
  std::string shown_key_;    // the heat map's
  std::string failed_key_;   // a view whose reference failed: not retried until it changes
  std::chrono::steady_clock::time_point changed_at_;
  vk::Image heat_map_;
};

}  // namespace prismoid::app
