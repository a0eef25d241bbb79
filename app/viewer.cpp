#include "app/viewer.hpp"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>
#include <stdexcept>

#include "renderer/frame/frame_renderer.hpp"
#include "renderer/vk/device.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/swapchain.hpp"

namespace prismoid::app {

namespace {

std::atomic<bool> g_terminate{false};
extern "C" void on_terminate_signal(int) { g_terminate = true; }

struct GlfwSession {
  GlfwSession() {
    glfwSetErrorCallback([](int code, const char* text) { std::fprintf(stderr, "[prismoid] GLFW error %d: %s\n", code, text); });
    if (!glfwInit()) throw std::runtime_error("cannot open a window: GLFW could not connect to a display (is DISPLAY set?)");
  }
  ~GlfwSession() { glfwTerminate(); }
};

struct Window {
  GLFWwindow* handle = nullptr;
  Window(uint32_t w, uint32_t h, const char* title) {
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
    handle = glfwCreateWindow(int(w), int(h), title, nullptr, nullptr);
    if (!handle) throw std::runtime_error("cannot create the window");
  }
  ~Window() { glfwDestroyWindow(handle); }
};

struct Surface {
  VkInstance instance;
  VkSurfaceKHR handle = VK_NULL_HANDLE;
  Surface(VkInstance i, GLFWwindow* w) : instance(i) {
    vk::check(glfwCreateWindowSurface(i, w, nullptr, &handle), "glfwCreateWindowSurface");
  }
  ~Surface() { vkDestroySurfaceKHR(instance, handle, nullptr); }
};

// Orbit camera: left drag rotates around the target, scroll zooms.
struct OrbitControl {
  Camera camera;
  double last_x = 0, last_y = 0;
  bool dragging = false;

  void rotate(double dx, double dy) {
    const glm::dvec3 offset = camera.eye - camera.target;
    const glm::dvec3 forward = glm::normalize(-offset);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, camera.up));
    glm::dmat4 yaw = glm::rotate(glm::dmat4(1.0), -dx * 0.01, camera.up);
    glm::dmat4 pitch = glm::rotate(glm::dmat4(1.0), -dy * 0.01, right);
    glm::dvec3 rotated = glm::dvec3(yaw * pitch * glm::dvec4(offset, 0.0));
    // Keep away from the pole, where up and the view direction would become parallel.
    if (glm::length(glm::cross(glm::normalize(rotated), glm::normalize(camera.up))) > 0.02) camera.eye = camera.target + rotated;
  }
  void zoom(double steps) {
    const glm::dvec3 offset = camera.eye - camera.target;
    camera.eye = camera.target + offset * std::pow(0.9, steps);
  }
};

VkExtent2D framebuffer_extent(GLFWwindow* w) {
  int fw = 0, fh = 0;
  glfwGetFramebufferSize(w, &fw, &fh);
  return {uint32_t(std::max(fw, 0)), uint32_t(std::max(fh, 0))};
}

void blit_to_swapchain(VkCommandBuffer cmd, const vk::Image& display, VkImage target, VkExtent2D extent) {
  vk::image_barrier(cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                    VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkImageBlit region{};
  region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.srcOffsets[1] = {int32_t(display.extent().width), int32_t(display.extent().height), 1};
  region.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.dstOffsets[1] = {int32_t(extent.width), int32_t(extent.height), 1};
  vkCmdBlitImage(cmd, display.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                 &region, VK_FILTER_NEAREST);
  vk::image_barrier(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                    VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_NONE,
                    VK_ACCESS_2_NONE);
}

void apply_action(GLFWwindow* w, const ViewerAction& a) {
  switch (a.kind) {
    case ViewerAction::Kind::Resize: glfwSetWindowSize(w, int(a.width), int(a.height)); break;
    case ViewerAction::Kind::Iconify: glfwIconifyWindow(w); break;
    case ViewerAction::Kind::Restore: glfwRestoreWindow(w); break;
    case ViewerAction::Kind::Close: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
  }
}

}  // namespace

bool display_available() {
  const char* x = std::getenv("DISPLAY");
  const char* wl = std::getenv("WAYLAND_DISPLAY");
  return (x && *x) || (wl && *wl);
}

ViewerReport run_viewer(const TetMesh& mesh, const ViewerOptions& options) {
  g_terminate = false;
  auto previous_term = std::signal(SIGTERM, on_terminate_signal);
  auto previous_int = std::signal(SIGINT, on_terminate_signal);
  struct RestoreSignals {
    decltype(previous_term) term, intr;
    ~RestoreSignals() { std::signal(SIGTERM, term); std::signal(SIGINT, intr); }
  } restore{previous_term, previous_int};

  GlfwSession glfw;
  if (!glfwVulkanSupported()) throw vk::NoSuitableDevice("GLFW found no Vulkan loader able to present");
  uint32_t ext_count = 0;
  const char** exts = glfwGetRequiredInstanceExtensions(&ext_count);
  vk::InstanceOptions instance_options;
  instance_options.validation = options.validation;
  for (uint32_t i = 0; i < ext_count; ++i) instance_options.extensions.emplace_back(exts[i]);
  vk::Instance instance(instance_options);
  const auto devices = vk::query_devices(instance.get());
  const auto& caps = vk::select_device(devices, options.device_index);
  vk::Device device(instance, caps, {.presentation = true});

  Window window(options.width, options.height, "Prismoid");
  Surface surface(instance.get(), window.handle);
  vk::Swapchain swapchain(device, surface.handle, framebuffer_extent(window.handle));

  frame::FrameRenderer renderer(device, mesh);
  OrbitControl control;
  control.camera = options.camera ? *options.camera : fit_camera(renderer.bounds());
  glfwSetWindowUserPointer(window.handle, &control);
  glfwSetScrollCallback(window.handle, [](GLFWwindow* w, double, double dy) {
    static_cast<OrbitControl*>(glfwGetWindowUserPointer(w))->zoom(dy);
  });

  vk::GpuTimer timer(device, 16);
  vk::UniqueSemaphore image_available = vk::create_semaphore(device);
  vk::UniqueFence in_flight = vk::create_fence(device, true);
  VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  alloc.commandPool = device.command_pool();
  alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  alloc.commandBufferCount = 1;
  VkCommandBuffer cmd;
  vk::check(vkAllocateCommandBuffers(device.get(), &alloc, &cmd), "vkAllocateCommandBuffers");

  ViewerReport report;
  report.device_name = caps.name;
  const frame::FrameSettings& settings = options.settings;
  bool timer_has_results = false;
  auto last_print = std::chrono::steady_clock::now();
  uint32_t frame_index = 0;

  while (!glfwWindowShouldClose(window.handle) && !g_terminate) {
    for (const auto& a : options.script)
      if (a.frame == frame_index) apply_action(window.handle, a);
    ++frame_index;
    if (options.max_frames && frame_index > options.max_frames) break;
    glfwPollEvents();

    // Mouse: orbit while the left button is held.
    double mx, my;
    glfwGetCursorPos(window.handle, &mx, &my);
    const bool pressed = glfwGetMouseButton(window.handle, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
    if (pressed && control.dragging) control.rotate(mx - control.last_x, my - control.last_y);
    control.dragging = pressed;
    control.last_x = mx;
    control.last_y = my;
    if (glfwGetKey(window.handle, GLFW_KEY_R) == GLFW_PRESS) control.camera = fit_camera(renderer.bounds());
    if (glfwGetKey(window.handle, GLFW_KEY_ESCAPE) == GLFW_PRESS) glfwSetWindowShouldClose(window.handle, GLFW_TRUE);

    const VkExtent2D fb = framebuffer_extent(window.handle);
    if (fb.width == 0 || fb.height == 0 || glfwGetWindowAttrib(window.handle, GLFW_ICONIFIED)) {
      ++report.frames_skipped_minimized;
      glfwWaitEventsTimeout(0.05);
      continue;
    }
    if (fb.width != swapchain.extent().width || fb.height != swapchain.extent().height) {
      swapchain.recreate(fb);
      ++report.swapchain_recreations;
    }

    vk::check(vkWaitForFences(device.get(), 1, in_flight.ptr(), VK_TRUE, UINT64_MAX), "vkWaitForFences");
    if (timer_has_results) {
      const auto timings = timer.read();
      const auto now = std::chrono::steady_clock::now();
      if (options.print_timings && now - last_print > std::chrono::seconds(1)) {
        std::ostringstream title;
        title << "Prismoid - " << caps.name << " -";
        for (const auto& t : timings) title << " " << t.name << " " << t.gpu_ms << " ms";
        glfwSetWindowTitle(window.handle, title.str().c_str());
        std::printf("%s\n", title.str().c_str());
        std::fflush(stdout);
        last_print = now;
      }
    }
    const auto index = swapchain.acquire(image_available.get());
    if (!index) {
      swapchain.recreate(framebuffer_extent(window.handle));
      ++report.swapchain_recreations;
      continue;
    }
    vk::check(vkResetFences(device.get(), 1, in_flight.ptr()), "vkResetFences");

    renderer.resize(swapchain.extent());
    renderer.prepare(control.camera, settings);  // the previous frame's fence has signalled
    vk::check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    timer.reset(cmd);
    renderer.record(cmd, control.camera, settings, timer);
    {
      vk::ScopedPass pass(timer, cmd, "present-blit");
      blit_to_swapchain(cmd, renderer.display(), swapchain.image(*index), swapchain.extent());
    }
    vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");

    VkPipelineStageFlags wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSemaphore done = swapchain.render_finished(*index);
    VkSemaphore acquired = image_available.get();
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &acquired;
    submit.pWaitDstStageMask = &wait_stage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &done;
    vk::check(vkQueueSubmit(device.queue(), 1, &submit, in_flight.get()), "vkQueueSubmit");
    timer_has_results = true;
    if (!swapchain.present(*index, done)) {
      swapchain.recreate(framebuffer_extent(window.handle));
      ++report.swapchain_recreations;
    }
    ++report.frames_presented;
  }
  device.wait_idle();
  vkFreeCommandBuffers(device.get(), device.command_pool(), 1, &cmd);
  report.validation_messages = instance.validation_log().count();
  return report;
}

}  // namespace prismoid::app
