#pragma once
// The surface modes: one table from which `render` parses --mode and lists the modes in its
// help, the surface window fills its mode menu, the bench sweeps, and the surface renderer plans
// and dispatches each frame (to the backend the mode names, with its indirect light). A mode
// is a line of the table; a backend is a folder under renderer/surface/ with a
// SurfaceBackendInfo (surface_backend.hpp). Mode names appear nowhere else but in tests.
#include <string>
#include <string_view>
#include <vector>

#include "renderer/frame/frame_plan.hpp"
#include "renderer/surface/surface_backend.hpp"

namespace prismoid::surface {

struct SurfaceMode {
  std::string_view name;
  std::string_view summary;                  // one line for the help text and the window's menu
  const SurfaceBackendInfo* backend = nullptr;  // nullptr: on the CPU (the path tracer), not in the window or the bench
  frame::SurfaceGi gi = frame::SurfaceGi::None;  // the indirect light it asks its backend for
  bool gpu() const { return backend != nullptr; }
};

// Every surface mode, in the order the window and the bench list them (GPU modes first).
const std::vector<SurfaceMode>& surface_mode_table();
// The mode of that name; nullptr for a name that is not a surface mode.
const SurfaceMode* find_surface_mode(std::string_view name);
// The mode of `backend` with indirect light `gi` (render's --gi picks it); nullptr when none.
const SurfaceMode* find_surface_mode(const SurfaceBackendInfo& backend, frame::SurfaceGi gi);
// The GPU modes this device can draw, in table order.
std::vector<std::string> surface_modes(const vk::Device& device);

}  // namespace prismoid::surface
