#include "prismoid_session.hpp"

#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <vector>

#include "renderer/vk/capabilities.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/instance.hpp"

namespace prismoid::paraview {

struct Session::Impl {
  // Made on the first frame, not when ParaView loads the plugin: a rank without a Vulkan
  // device can load it and fail only when asked to draw.
  std::optional<vk::Instance> instance;
  std::vector<vk::DeviceCapabilities> devices;
  std::optional<vk::Device> device;
  std::string key;
  std::unique_ptr<TetMesh> mesh;  // the renderer keeps what it uploaded; this is kept for the CPU passes
  std::unique_ptr<frame::FrameRenderer> renderer;

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
  impl_->renderer.reset();
  impl_->mesh = std::make_unique<TetMesh>(std::move(mesh));
  impl_->key = key;
  return true;
}

frame::OffscreenFrame Session::render(const Camera& camera, const frame::FrameSettings& settings, uint32_t width, uint32_t height) {
  if (!impl_->mesh) throw std::logic_error("prismoid::paraview::Session: render before set_mesh");
  impl_->ensure_device();
  if (!impl_->renderer) impl_->renderer = std::make_unique<frame::FrameRenderer>(*impl_->device, *impl_->mesh);
  return impl_->renderer->render_offscreen(camera, settings, {width, height});
}

std::string Session::device_name() const { return impl_->device ? impl_->device->capabilities().name : std::string(); }

}  // namespace prismoid::paraview
