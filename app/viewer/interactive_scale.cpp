#include "app/viewer/interactive_scale.hpp"

#include <algorithm>

namespace prismoid::app {

void InteractiveScale::update(bool moving, double frame_ms, uint32_t frame_level) {
  if (frame_ms > 0.0 && frame_level <= kCoarsestProxy) measured_ms_[frame_level] = frame_ms;
  if (!moving) {  // still: full resolution (the level the motion ended on is kept for the next)
    moving_ = false;
    level_ = 0;
    return;
  }
  if (!moving_) {  // the camera starts moving again: where the last motion ended
    moving_ = true;
    move_to(proxy_allowed_ || moving_level_ < kProxy ? moving_level_ : kCoarsest);  // no proxy now: the coarsest resolution
    return;
  }
  uint32_t next = level_;
  if (const double here = measured_ms_[level_]; here > 0.0) {  // else: wait for this level's first frame
    if (here > target_ms_) {
      next = std::min(proxy_allowed_ ? kCoarsestProxy : kCoarsest, level_ + 1);
    } else if (level_ > 0) {
      // With a fifth of headroom, so that the level does not flicker between two.
      const double finer = measured_ms_[level_ - 1];
      if ((finer > 0.0 ? finer : 4.0 * here) <= 0.8 * target_ms_) next = level_ - 1;
    }
  }
  move_to(next);
}

void InteractiveScale::move_to(uint32_t level) {
  if (level != level_) measured_ms_[level] = 0.0;  // a fresh time at the new level before the next step
  level_ = level;
  moving_level_ = level;
}

namespace {

VkExtent2D shrunk(VkExtent2D window, uint32_t shift) { return {std::max(1u, window.width >> shift), std::max(1u, window.height >> shift)}; }

}  // namespace

VkExtent2D InteractiveScale::extent(VkExtent2D window) const { return shrunk(window, std::min(level_, kCoarsest)); }

VkExtent2D InteractiveScale::proxy_extent(VkExtent2D window) { return shrunk(window, kCoarsest); }

}  // namespace prismoid::app
