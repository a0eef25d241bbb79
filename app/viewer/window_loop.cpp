#include "app/viewer/window_loop.hpp"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>

#include "app/viewer/present_thread.hpp"
#include "app/viewer/window_input.hpp"
#include "renderer/vk/frame_submission.hpp"
#include "renderer/vk/error.hpp"

namespace prismoid::app {

namespace {

std::atomic<bool> g_terminate{false};
extern "C" void on_terminate_signal(int) { g_terminate = true; }

}  // namespace

TerminateSignals::TerminateSignals() {
  g_terminate = false;
  previous_term_ = std::signal(SIGTERM, on_terminate_signal);
  previous_int_ = std::signal(SIGINT, on_terminate_signal);
}

TerminateSignals::~TerminateSignals() {
  std::signal(SIGTERM, previous_term_);
  std::signal(SIGINT, previous_int_);
}

bool TerminateSignals::requested() { return g_terminate; }

void run_window_loop(WindowParts& parts, WindowContent& content, const ViewerOptions& options, ViewerReport& report) {
  Window& window = parts.window;
  const vk::Device& device = parts.device;
  vk::Swapchain& swapchain = parts.swapchain;
  ImGuiLayer& ui = parts.ui;

  vk::GpuTimer timer(device, 32);  // a split view records two modes' passes in one frame
  vk::FrameResources frame_resources(device);
  const VkSemaphore image_available = frame_resources.image_available.get();
  const vk::UniqueFence& in_flight = frame_resources.in_flight;
  const VkCommandBuffer cmd = frame_resources.cmd;

  auto recreate = [&] { recreate_swapchain(swapchain, window, ui, report); };
  auto finish_frame_capture = [&] {
    finish_capture(parts.capture, report, content.inputs(), [&](const std::string& m) { content.capture_failed(m); });
  };

  bool frame_in_flight = false;
  PresentThread presenter;  // the frame's submission and presentation: the loop keeps reading input meanwhile
  MouseState mouse;
  glfwGetCursorPos(window.get(), &mouse.last.x, &mouse.last.y);
  auto last_frame = std::chrono::steady_clock::now();
  auto last_print = last_frame;
  auto last_input = last_frame;
  uint32_t& frame_index = content.frame_index();

  // Mouse, wheel and held keys to the camera (keys and dropped files wait in the window for the
  // next frame: what they do may need the queue). `seconds`: since the input was last read.
  auto read_input = [&] {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::min(std::chrono::duration<double>(now - last_input).count(), 0.1);
    report.longest_input_gap_ms = std::max(report.longest_input_gap_ms, std::chrono::duration<double, std::milli>(now - last_input).count());
    last_input = now;
    handle_mouse(window, content.camera(), mouse, swapchain.extent(), content.show_ui() && ui.wants_mouse(),
                 content.show_ui() && ui.wants_keyboard(), seconds);
    content.pointer_held(mouse.dragging);  // handle_mouse's drag on the view (one begun on a panel is the panel's)
  };
  // Whether the frame handed over is still being submitted and presented, or drawn by the GPU.
  auto drawing = [&] {
    if (presenter.handed()) {
      const std::optional<bool> current = presenter.poll();
      if (!current) return true;
      if (!*current) recreate();  // presentation found the swapchain out of date
    }
    return frame_in_flight && vkGetFenceStatus(device.get(), in_flight.get()) == VK_NOT_READY;
  };

  while (!glfwWindowShouldClose(window.get()) && !TerminateSignals::requested()) {
    if (drawing()) {  // only input until the frame ends: rendering never blocks it
      glfwWaitEventsTimeout(0.004);
      read_input();
      ++report.input_reads_while_drawing;
      continue;
    }
    if (std::function<void()> work = content.setup_work()) {
      presenter.hand_over([work = std::move(work)] {
        work();
        return true;  // the swapchain untouched
      });
      continue;
    }
    content.run_due();
    ++frame_index;
    if (options.max_frames && frame_index > options.max_frames) break;
    glfwPollEvents();
    const auto now = std::chrono::steady_clock::now();
    content.frame_started(std::chrono::duration<double, std::milli>(now - last_frame).count());
    last_frame = now;
    read_input();
    for (const KeyPress& key : window.take_keys())
      if (!(content.show_ui() && ui.wants_keyboard())) content.on_key(key);
    for (const auto& dropped : window.take_drops()) content.on_drop(dropped);

    const VkExtent2D fb = window.framebuffer_extent();
    if (fb.width == 0 || fb.height == 0 || glfwGetWindowAttrib(window.get(), GLFW_ICONIFIED)) {
      ++report.frames_skipped_minimized;
      glfwWaitEventsTimeout(0.05);
      continue;
    }
    if (fb.width != swapchain.extent().width || fb.height != swapchain.extent().height) recreate();

    vk::check(vkWaitForFences(device.get(), 1, in_flight.ptr(), VK_TRUE, UINT64_MAX), "vkWaitForFences");
    if (frame_in_flight) {  // the last frame finished: its numbers and its screenshot
      content.frame_finished(timer.read(), false);
      finish_frame_capture();
      frame_in_flight = false;
      if (options.print_timings && now - last_print > std::chrono::seconds(1)) {
        const std::string line = content.timings_line();
        glfwSetWindowTitle(window.get(), line.c_str());
        std::printf("%s\n", line.c_str());
        std::fflush(stdout);
        last_print = now;
      }
    }

    ui.begin_frame();
    content.draw_ui();
    ui.finish_frame();
    content.prepare_frame(swapchain.extent());

    const auto index = swapchain.acquire(image_available);
    if (!index) {
      recreate();
      continue;
    }
    vk::check(vkResetFences(device.get(), 1, in_flight.ptr()), "vkResetFences");
    vk::check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vk::check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
    timer.reset(cmd);
    content.record(cmd, timer, swapchain.image(*index), swapchain.extent());
    {
      vk::ScopedPass pass(timer, cmd, "ui");
      ui.record(cmd, *index, content.show_ui());
    }
    if (const std::optional<std::string> path = content.take_capture())
      parts.capture.record(cmd, swapchain.image(*index), swapchain.extent(), swapchain.format(), *path);
    vk::check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    const VkSemaphore rendered = swapchain.render_finished(*index);
    presenter.hand_over([&device, &swapchain, cmd, image_available, rendered, fence = in_flight.get(), image = *index] {
      vk::submit_frame(device, cmd, image_available, rendered, fence);
      return swapchain.present(image, rendered);
    });
    frame_in_flight = true;
    ++report.frames_presented;
  }
  presenter.wait();  // an out-of-date swapchain no longer matters: the window is closing
  content.stopping();
  device.wait_idle();
  if (frame_in_flight) {
    content.frame_finished(timer.read(), true);
    finish_frame_capture();
  }
}

}  // namespace prismoid::app
