#pragma once
// The compute backend: cells binned into 8x8 tiles and sorted there by depth on the GPU, then
// each pixel's exact interval through every cell of its tile found on its own ray, composited
// in the pixel's own depth order (compute_intervals.hpp). It runs on every core of a GPU whose
// rasterizer is narrow, and needs no mesh shaders.
#include <memory>

#include "renderer/volume/compute/compute_intervals.hpp"
#include "renderer/volume/volume_backend.hpp"

namespace prismoid::volume {

const VolumeBackendInfo& compute_backend();

class ComputeBackend final : public GpuVolumeBackend {
 public:
  explicit ComputeBackend(const BackendScene& scene);
  void check(const BackendPrepare& frame) override;
  BackendHistory history(const frame::FrameSettings& settings) const override;
  bool run_cpu(const frame::PlannedPass& pass, const BackendPrepare& frame) override;
  void prepared(const BackendPrepare& frame, const frame::FramePlan& plan, frame::FrameReport& report) override;
  bool record(const frame::PlannedPass& pass, const BackendRecord& frame) override;
  AccumulatedBy accumulated_by() const override { return AccumulatedBy::Compute; }
  void recorded(const frame::FrameSettings& settings) override;
  void forget_history() override {}
  bool finished(const frame::FrameSettings& settings, frame::FrameReport& report) override;

  const ComputeIntervals& intervals() const { return intervals_; }

 private:
  const GpuTetMesh& mesh_;
  ComputeIntervals intervals_;
};

}  // namespace prismoid::volume
