#pragma once
// The mesh-shader backend (interval shading, Tricard 2024): a mesh-shader workgroup emits each
// cell's proxy geometry and the rasterizer's fragments integrate each pixel's interval through
// it. It draws cells in the order the mode asks for: as stored, sorted by centroid distance on
// the GPU (visibility_sort), or in the exact topological order made on the CPU.
#include <memory>

#include "renderer/volume/mesh/interval_shading.hpp"
#include "renderer/volume/mesh/visibility_sort.hpp"
#include "renderer/volume/volume_backend.hpp"

namespace prismoid::volume {

const VolumeBackendInfo& mesh_backend();

class MeshBackend final : public GpuVolumeBackend {
 public:
  explicit MeshBackend(const BackendScene& scene);
  ~MeshBackend() override;
  void check(const BackendPrepare& frame) override;
  BackendHistory history(const frame::FrameSettings& settings) const override;
  bool run_cpu(const frame::PlannedPass& pass, const BackendPrepare& frame) override;
  void prepared(const BackendPrepare& frame, const frame::FramePlan& plan, frame::FrameReport& report) override;
  bool record(const frame::PlannedPass& pass, const BackendRecord& frame) override;
  AccumulatedBy accumulated_by() const override { return AccumulatedBy::Raster; }
  void recorded(const frame::FrameSettings& settings) override;
  void forget_history() override { recorded_order_.reset(); }
  bool finished(const frame::FrameSettings& settings, frame::FrameReport& report) override;
  std::optional<DrawCounts> draw_counts() const override;

  // The GPU visibility sort; nullptr until a frame planned a sort.
  const VisibilitySort* gpu_sort() const { return gpu_sort_.get(); }

 private:
  struct Orders;  // the CPU's exact order and the tetlets, made on first use
  const vk::Device& device_;
  const GpuTetMesh& mesh_;
  IntervalShadingPass interval_;
  std::unique_ptr<Orders> orders_;
  std::unique_ptr<VisibilitySort> gpu_sort_;
  const vk::Buffer* order_ = nullptr;           // what the next record() draws with (nullptr: mesh order)
  const GpuTetlets* draw_tetlets_ = nullptr;    // what the next record() draws (nullptr: cells)
  std::optional<frame::Ordering> recorded_order_;  // the ordering that made the order buffer the last frame drew with
};

}  // namespace prismoid::volume
