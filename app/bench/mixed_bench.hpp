#pragma once
// The bench's mixed rows (issue "One renderer for every front end"): what each surface mode costs
// under a volume, on each GPU volume backend. One scene per run: the volume the bench's first
// dataset names, cut by an opaque square through its centre facing the camera (the volume's rays
// end there), drawn through the renderer facade and measured against the mixed frame's CPU
// double-precision reference (the surfaces' direct light, the volume up to them, the composite).
#include <cstdint>
#include <vector>

#include "app/bench/bench_table.hpp"
#include "app/common/volume_options.hpp"
#include "scene/bounds.hpp"
#include "scene/camera.hpp"
#include "scene/surface_scene.hpp"

namespace prismoid::vk {
class Device;
}

namespace prismoid::bench {

struct MixedBenchOptions {
  uint32_t width = 96, height = 72;
  uint32_t frames = 3;
  double warm_up_seconds = 0.0;  // before each row's timed frames (timing::warm_up); at least one frame
};

// The square the volume is cut by: through the centre of `bounds`, perpendicular to the camera's
// view axis, half the bounds' diagonal across, lit by the default key light and sky.
SurfaceScene cutting_square(const Bounds& bounds, const Camera& camera);

// A row per GPU surface mode without indirect light that `device` draws, on each GPU volume
// backend of the table it runs; shadows off (the reference's direct light then needs no rays).
std::vector<BenchRow> bench_mixed(const vk::Device& device, const app::VolumeChoice& volume, const Camera& camera,
                                  const MixedBenchOptions& options);

}  // namespace prismoid::bench
