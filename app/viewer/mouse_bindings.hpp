#pragma once
// Which camera gesture a mouse drag makes, ParaView's way, and applying it. Pure logic, so the
// bindings are tested without a window.
#include <glm/vec2.hpp>
#include <optional>

#include "app/viewer/camera_controller.hpp"

namespace prismoid::app {

struct MouseButtons {
  bool left = false, middle = false, right = false, shift = false;
};

enum class DragGesture { Rotate, Pan, Zoom, Look };

// Left: rotate (fly mode: look); shift+left or middle: pan; right: zoom. nullopt: no button.
std::optional<DragGesture> drag_gesture(const MouseButtons& buttons, bool flying);

// Applies a drag of `pixels` (screen y down). Right drag up zooms in, 20 pixels a wheel step.
void apply_drag(CameraController& camera, DragGesture gesture, glm::dvec2 pixels, glm::dvec2 viewport);

}  // namespace prismoid::app
