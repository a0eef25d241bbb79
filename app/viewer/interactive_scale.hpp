#pragma once
// The window's resolution while the camera moves. A frame that cannot keep up with a moving
// camera makes the window feel frozen (on lavapipe a 200k-cell colour frame at 1280x800 takes
// seconds), so while the camera moves the volume is drawn at 1/2, 1/4 or 1/8 of the window per
// side, the coarsest that is needed to hold the target frame time, and shown scaled up; the
// frame after the camera stops is drawn at full resolution again. Where full resolution holds the
// target (a GPU), nothing changes. Pure logic, so its rule is tested without a window.
#include <array>
#include <cstdint>

#include <vulkan/vulkan.h>

namespace prismoid::app {

class InteractiveScale {
 public:
  static constexpr uint32_t kCoarsest = 3;  // 1/8 per side
  // Further steps where the caller has coarse proxies of the data (scene/coarse_proxy.hpp): the
  // proxies' fewer cells, at 1/8 per side, for data whose cost is per cell rather than per
  // pixel: kProxy the finer proxy, kCoarsestProxy the coarser.
  static constexpr uint32_t kProxy = 4, kCoarsestProxy = 5;
  explicit InteractiveScale(double target_ms = 100.0) : target_ms_(target_ms) {}

  // Once per frame, before it is drawn: whether the camera moved since the last frame, and the
  // time of the last finished frame with the level it was drawn at (ms 0: none yet). Picks this
  // frame's level: 0 when still; when the camera starts moving, the level the last motion ended
  // on; while it moves, one level coarser once a frame at the current level missed the target,
  // one finer when the finer level's last time held it (or, not seen yet, when four times this
  // level's would: the finer level has four times the pixels).
  void update(bool moving, double frame_ms, uint32_t frame_level);

  void allow_proxy(bool allowed) { proxy_allowed_ = allowed; }
  uint32_t level() const { return level_; }
  bool proxy() const { return level_ >= kProxy; }
  uint32_t proxy_index() const { return level_ - kProxy; }  // 0: the finer proxy (when proxy())
  bool moving() const { return moving_; }
  double target_ms() const { return target_ms_; }
  // The size the volume is drawn at for a window of `window` pixels (at least 1x1; the proxy at 1/8).
  VkExtent2D extent(VkExtent2D window) const;
  // The size a proxy is drawn at (1/8 per side).
  static VkExtent2D proxy_extent(VkExtent2D window);

 private:
  double target_ms_;
  void move_to(uint32_t level);
  uint32_t level_ = 0;
  uint32_t moving_level_ = 0;  // the level of the last moving frame
  bool moving_ = false;
  // The last frame time seen at each level (0: none since the window last switched to it).
  std::array<double, kCoarsestProxy + 1> measured_ms_{};
  bool proxy_allowed_ = false;
};

}  // namespace prismoid::app
