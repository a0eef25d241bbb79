#include "prismoid_session.hpp"

#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <vector>

#include "renderer/frame/volume_modes.hpp"
#include "renderer/mixed/scene_renderer.hpp"
#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"

namespace prismoid::paraview {

struct Session::Impl {
  // Made on the first frame, not when ParaView loads the plugin: a rank without a Vulkan
  // device can load it and fail only when asked to draw. Kept across meshes (the facade is
  // made again for each mesh, on this device).
  std::optional<vk::Instance> instance;
  std::vector<vk::DeviceCapabilities> devices;
  std::optional<vk::Device> device;
  std::string key;
  std::unique_ptr<TetMesh> mesh;  // the facade keeps a pointer to it
  std::unique_ptr<mixed::SceneRenderer> renderer;

  void ensure_device() {
    if (device) return;
    vk::InstanceOptions options;
    // PRISMOID_VALIDATION=1 turns on the validation layers (the plugin's tests do).
    const char* validation = std::getenv("PRISMOID_VALIDATION");
    options.validation = validation && std::string(validation) == "1";
    instance.emplace(options);
    devices = vk::query_devices(instance->get());
    const vk::DeviceCapabilities& caps = vk::select_device(devices, std::nullopt);
    device.emplace(*instance, caps, vk::DeviceOptions{});
  }
};

Session::Session() : impl_(std::make_unique<Impl>()) {}
Session::~Session() {
  impl_->renderer.reset();
  impl_->device.reset();
}

Session& Session::instance() {
  static Session session;
  return session;
}

bool Session::has_mesh(const std::string& key) const { return impl_->mesh && impl_->key == key; }

bool Session::set_mesh(const std::string& key, TetMesh mesh) {
  if (has_mesh(key)) return false;
  validate(mesh);
  auto next = std::make_unique<TetMesh>(std::move(mesh));
  // A time step of a static mesh (ParaView's time moved): the renderer sends its fields alone;
  // another mesh is uploaded whole by the next frame (SceneRenderer::set_volume compares them).
  if (impl_->renderer) impl_->renderer->set_volume(*next);
  impl_->mesh = std::move(next);
  impl_->key = key;
  return true;
}

frame::OffscreenFrame Session::render(const Camera& camera, const frame::FrameSettings& settings, uint32_t width, uint32_t height) {
  if (!impl_->mesh) throw std::logic_error("prismoid::paraview::Session: render before set_mesh");
  impl_->ensure_device();
  if (!impl_->renderer) impl_->renderer = std::make_unique<mixed::SceneRenderer>(mixed::SceneData{.volume = impl_->mesh.get()}, *impl_->device);
  mixed::SceneSettings scene;
  scene.size = {width, height};
  scene.volume_mode = frame::find_volume_mode(settings.ordering, false);
  if (!scene.volume_mode) throw std::logic_error("prismoid::paraview::Session: no GPU volume mode draws in that order");
  scene.volume = settings;
  scene.interactive = true;
  return std::move(*impl_->renderer->render(camera, scene).volume);
}

uint32_t Session::mesh_uploads() const { return impl_->renderer ? impl_->renderer->volume_uploads().meshes : 0; }
uint32_t Session::field_uploads() const { return impl_->renderer ? impl_->renderer->volume_uploads().fields : 0; }

std::string Session::device_name() const { return impl_->device ? impl_->device->capabilities().name : std::string(); }

}  // namespace prismoid::paraview
