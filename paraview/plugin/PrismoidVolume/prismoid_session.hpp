#pragma once
// The plugin's VTK-free half: one Vulkan device per process (made on the first frame) and the
// renderer facade (mixed::SceneRenderer, as every front end draws) over the mesh last drawn. It includes nothing of VTK, so that the boundary
// between ParaView's VTK and Prismoid's core stays in one place (vtk_to_prismoid.hpp is the
// other side).
#include <cstdint>
#include <memory>
#include <string>

#include "renderer/frame/frame_report.hpp"
#include "renderer/frame/frame_plan.hpp"
#include "scene/camera.hpp"
#include "scene/tet_mesh.hpp"

namespace prismoid::paraview {

class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  // The process's session (ParaView renders on one thread).
  static Session& instance();

  // Replaces the mesh the next frames draw; `key` names it (the caller's modification times),
  // so the same mesh given twice is uploaded once, and a mesh with the points and cells of the
  // one before (a time step of a static mesh) sends only its fields. Whether it was replaced.
  bool set_mesh(const std::string& key, TetMesh mesh);
  bool has_mesh(const std::string& key) const;

  // One interactive frame of the mesh (a still camera reuses the last frame's order), read back
  // (row 0 at the top), drawn by the GPU mode of settings.ordering. Throws vk::NoSuitableDevice when no
  // Vulkan device can render it, InputError for settings the mesh or device refuses.
  frame::OffscreenFrame render(const Camera& camera, const frame::FrameSettings& settings, uint32_t width, uint32_t height);
  // What the session's renderer has sent to the GPU: whole meshes, and fields alone.
  uint32_t mesh_uploads() const;
  uint32_t field_uploads() const;
  // The device's name (after the first frame; empty before).
  std::string device_name() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace prismoid::paraview
