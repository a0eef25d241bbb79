#pragma once
// What `--volume-backend auto` draws a volume's intervals with on a device: the backend whose
// calibration frame was faster there. The choice is measured, never a list of GPU names: a
// GPU with a full graphics pipeline may favour the mesh-shader backend, a compute GPU (whose
// rasterizer runs on a few of its units) or a CPU device (lavapipe) the compute one.
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "renderer/frame/frame_plan.hpp"

namespace prismoid::vk {
class Device;
}  // namespace prismoid::vk

namespace prismoid::frame {

// One device's calibration: the best GPU time of the same frame drawn by each GPU backend of
// the volume backend table that the device runs.
struct BackendCalibration {
  std::string device_key;  // device name, driver version and pipeline-cache UUID: what it was measured on
  // Best of the timed frames, all passes of the frame, by backend name (absent or not finite:
  // not measured).
  std::map<std::string, double, std::less<>> ms;
  uint64_t cells = 0;      // the calibration mesh's cells
  uint32_t width = 0, height = 0;
};

struct BackendChoice {
  IntervalBackend backend = IntervalBackend::Mesh;
  std::string reason;  // why, with the calibration's numbers, for info --plan and the stats
};

// The fastest GPU backend of the calibration, among the table's; the table's first (the
// default) where none could be timed.
BackendChoice choose_backend(const BackendCalibration& calibration);

// "name driver-version uuid-hex": changes with a driver update, which may change the answer.
std::string device_key(const vk::Device& device);

// Draws the calibration frame (a 12^3-cube box of 10,368 cells with a varying field, optical
// depth at 128x128, the camera framing it) with each GPU backend of the table the device runs, `frames` timed frames after one
// untimed, and returns the best times. About a second on lavapipe, milliseconds on a GPU.
BackendCalibration calibrate_backends(const vk::Device& device, uint32_t frames = 3);

}  // namespace prismoid::frame
