#pragma once
// One frame of a scene, recorded the same way for the window and for offscreen images.
// (The frame planner that decides which passes run grows here; today a volume frame is an
// optional visibility ordering, interval shading, and the resolve pass.)
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "renderer/vk/timer.hpp"
#include "renderer/volume/interval_shading.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::frame {

// The order cells are drawn in. It matters only for order-dependent quantities (colour);
// order-independent ones always draw in mesh order and never sort.
enum class Ordering {
  MeshOrder,  // as stored: exact only for order-independent quantities
  GpuSort,    // per-frame radix sort on the GPU by centroid distance (approximate)
  Exact,      // topological order over face adjacency (MPVONC): exact for convex acyclic meshes
};
const char* ordering_name(Ordering ordering);

struct FrameSettings {
  volume::ResolveSettings resolve;
  Ordering ordering = Ordering::GpuSort;
};

// What ran, besides the GPU passes: the ordering actually used and CPU work done.
struct FrameReport {
  std::string ordering = "none";        // "none (order-independent)", "gpu-sort", "exact", ...
  bool order_exact = false;              // whether the order was exact for every ray
  std::vector<vk::PassTiming> cpu_passes;  // CPU stages (milliseconds of wall time)
  uint64_t mesh_bytes = 0;               // the mesh's GPU buffers (positions, cells, fields)
  double tetlet_points_per_cell = 0.0;   // with shared vertices: points loaded per cell drawn (4 without)
  // What the interval pass drew (offscreen frames, on devices with pipeline statistics).
  bool counted = false;
  uint64_t primitives = 0;  // proxy triangles that reached the rasterizer's clipper
  uint64_t fragments = 0;   // fragment-shader invocations: (pixel, segment) pairs shaded
};

struct OffscreenFrame {
  uint32_t width = 0, height = 0;
  std::vector<float> quantity;  // one value per pixel, row 0 at the top
  std::vector<float> display;   // linear RGBA per pixel
  std::vector<float> emission;  // colour: premultiplied RGB and alpha per pixel; isosurface: shaded
                                // RGB and the distance from the eye to the hit (0: none)
  std::vector<vk::PassTiming> passes;
  FrameReport report;
};

class FrameRenderer {
 public:
  FrameRenderer(const vk::Device& device, const TetMesh& mesh);
  ~FrameRenderer();

  // (Re)creates the targets when the size changes.
  void resize(VkExtent2D extent);
  VkExtent2D extent() const { return targets_.extent; }

  // CPU work before a frame is recorded (outside any command buffer, with no frame of this
  // renderer in flight): pre-integration table, exact visibility order.
  FrameReport prepare(const Camera& camera, const FrameSettings& settings);
  // Records the frame's passes; the display and quantity images end in TRANSFER_SRC layout.
  void record(VkCommandBuffer cmd, const Camera& camera, const FrameSettings& settings, vk::GpuTimer& timer);
  const vk::Image& display() const { return targets_.display; }
  const vk::Image& quantity() const { return targets_.quantity; }

  // Prepares, renders, waits, reads the images back and returns them with the timings.
  OffscreenFrame render_offscreen(const Camera& camera, const FrameSettings& settings, VkExtent2D extent);

  const Bounds& bounds() const { return bounds_; }
  const volume::IntervalShadingPass& interval_pass() const { return interval_; }

 private:
  struct Orderings;
  const vk::Device& device_;
  volume::GpuTetMesh mesh_;
  Bounds bounds_;
  volume::IntervalShadingPass interval_;
  std::unique_ptr<Orderings> orderings_;
  volume::VolumeTargets targets_;
  vk::GpuTimer offscreen_timer_;
};

}  // namespace prismoid::frame
