#pragma once
// One frame of a scene, recorded the same way for the window and for offscreen images.
// (The frame planner that decides which passes run grows here; today a volume frame is
// interval shading followed by the resolve pass.)
#include <cstdint>
#include <vector>

#include "renderer/vk/timer.hpp"
#include "renderer/volume/interval_shading.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

struct FrameSettings {
  volume::ResolveSettings resolve;
};

struct OffscreenFrame {
  uint32_t width = 0, height = 0;
  std::vector<float> quantity;  // one value per pixel, row 0 at the top
  std::vector<float> display;   // linear RGBA per pixel
  std::vector<vk::PassTiming> passes;
};

class FrameRenderer {
 public:
  FrameRenderer(const vk::Device& device, const TetMesh& mesh);

  // (Re)creates the targets when the size changes.
  void resize(VkExtent2D extent);
  VkExtent2D extent() const { return targets_.extent; }

  // Records the frame's passes; the display and quantity images end in TRANSFER_SRC layout.
  void record(VkCommandBuffer cmd, const Camera& camera, const FrameSettings& settings, vk::GpuTimer& timer);
  const vk::Image& display() const { return targets_.display; }
  const vk::Image& quantity() const { return targets_.quantity; }

  // Renders, waits, reads the images back and returns them with the per-pass GPU times.
  OffscreenFrame render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent);

  const Bounds& bounds() const { return bounds_; }

 private:
  const vk::Device& device_;
  volume::GpuTetMesh mesh_;
  Bounds bounds_;
  volume::IntervalShadingPass interval_;
  volume::VolumeTargets targets_;
  vk::GpuTimer offscreen_timer_;
};

}  // namespace prismoid::frame
