#pragma once
// The CPU reference as a volume backend: every pixel's ray through the cells in double
// precision and exact per-pixel order (renderer/volume/cpu/reference_frame.hpp), or through the
// analytic field itself. It draws whole frames without a device: what every GPU backend is
// measured against, and what `--volume-backend cpu` (or `--mode reference`) shows.
#include "renderer/volume/volume_backend.hpp"

namespace prismoid::volume {

const VolumeBackendInfo& cpu_backend();

}  // namespace prismoid::volume
