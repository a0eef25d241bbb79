#pragma once
// The CLI's one text writer and one JSON writer of a frame's typed stats (mixed::FrameStats, filled
// by the renderer facade): `render` prints and writes --stats through these for a volume, surfaces
// on the GPU, or a volume inside its surfaces, so each counter is written once here. The JSON keys
// are those the user guide lists ("The stats file").
#include <cstddef>
#include <string>

#include "app/common/reference_accuracy.hpp"
#include "app/common/stats_json.hpp"
#include "renderer/mixed/frame_stats.hpp"

namespace prismoid::app {

// What the verb adds to the frame: the image it wrote, what the validation layer said, and the
// frame's distance from its CPU reference where it was measured.
struct FrameOutput {
  std::string image;
  size_t validation_messages = 0;
  const ReferenceAccuracy* accuracy = nullptr;
};

// What `render` prints of a frame: "wrote IMAGE (...) on DEVICE", then a line a part.
std::string frame_text(const mixed::FrameStats& stats, const FrameOutput& output);
// The --stats object of a frame.
StatsJson frame_json(const mixed::FrameStats& stats, const FrameOutput& output);

}  // namespace prismoid::app
