#include "app/viewer/mouse_bindings.hpp"

namespace prismoid::app {

std::optional<DragGesture> drag_gesture(const MouseButtons& b, bool flying) {
  if (b.left && flying && !b.shift) return DragGesture::Look;
  if ((b.left && b.shift) || b.middle) return DragGesture::Pan;
  if (b.left) return DragGesture::Rotate;
  if (b.right) return DragGesture::Zoom;
  return std::nullopt;
}

void apply_drag(CameraController& camera, DragGesture gesture, glm::dvec2 pixels, glm::dvec2 viewport) {
  switch (gesture) {
    case DragGesture::Rotate: camera.rotate(pixels, viewport); break;
    case DragGesture::Pan: camera.pan(pixels, viewport); break;
    case DragGesture::Zoom: camera.zoom(-pixels.y / 20.0); break;
    case DragGesture::Look: camera.fly_look(pixels, viewport); break;
  }
}

}  // namespace prismoid::app
