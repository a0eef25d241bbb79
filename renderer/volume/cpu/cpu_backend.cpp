#include "renderer/volume/cpu/cpu_backend.hpp"

#include "renderer/volume/cpu/reference_frame.hpp"

namespace prismoid::volume {

const VolumeBackendInfo& cpu_backend() {
  static const VolumeBackendInfo info{
      .name = "cpu",
      .summary = "the CPU reference: double precision, exact per-pixel order (of a field:, grid: or .vdb dataset, the field itself)",
      .needs = {},
      .supports = {.march = true, .depth_limit = true},
      .render = frame::reference_of,
  };
  return info;
}

}  // namespace prismoid::volume
