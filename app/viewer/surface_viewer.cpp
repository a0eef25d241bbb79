#include "app/viewer/surface_viewer.hpp"

#include <imgui.h>

#include <algorithm>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "app/common/output_files.hpp"
#include "app/viewer/camera_line.hpp"
#include "app/viewer/imgui_layer.hpp"
#include "app/viewer/screenshot.hpp"
#include "app/viewer/viewer_session.hpp"
#include "app/viewer/window.hpp"
#include "app/viewer/window_input.hpp"
#include "app/viewer/window_loop.hpp"
#include "io/image_io.hpp"
#include "renderer/surface/surface_renderer.hpp"
#include "renderer/vk/error.hpp"
#include "renderer/vk/instance.hpp"
#include "renderer/vk/memory.hpp"
#include "renderer/vk/swapchain.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

// Everything one surface window holds; the loop is run_surface_viewer's.
struct SurfaceSession {
  Window& window;
  const vk::Device& device;
  vk::Swapchain& swapchain;
  surface::SurfaceRenderer& renderer;
  CameraController camera;
  Bounds bounds;
  ViewerReport& report;
  std::string mode;
  // Split view: the left half shows `mode`, the right half `compare_mode` (the same camera, each
  // frame both drawn in full by the one renderer); B toggles it, `compare split|off` and
  // `compare-mode NAME` script it.
  bool split = false;
  std::string compare_mode;
  std::vector<vk::PassTiming> compare_passes;
  size_t left_passes = 0;  // of the last recorded frame's timed passes, how many were the left mode's
  bool show_ui = true;
  std::string panel_message;
  std::optional<std::string> capture_path;
  uint32_t screenshot_count = 0;
  std::vector<vk::PassTiming> passes;
  surface::SurfaceRenderer::FrameCounts counts;
  double cpu_frame_ms = 0.0;
  std::vector<std::string> inputs;  // the scene's file: no output of the window may replace it

  double aspect() const {
    const VkExtent2D e = swapchain.extent();
    return e.height ? double(e.width) / double(e.height) : 1.0;
  }
  void message(const std::string& text) {
    if (text.empty()) return;
    panel_message = text;
    report.messages.push_back(text);
    std::cerr << "prismoid: " << text << "\n";
  }
  void set_mode(const std::string& name) {
    const std::string problem = renderer.mode_problem(name);
    if (problem.empty()) mode = name;
    message(problem);
  }
  void set_shadows(bool on) {
    try {
      renderer.set_shadows(on);
    } catch (const vk::NoSuitableDevice& e) {
      message(e.what());
    }
  }
  // T: msa shades every frame, or every 4th, 8th or 16th while the camera moves (the atlas's
  // temporal amortization; the panel shows it).
  void next_amortization() {
    const uint32_t n = renderer.msa_amortization();
    renderer.set_msa_amortization(n == 0 ? 4 : n >= 16 ? 0 : 2 * n);
  }
  // K: msa's meshlet charts, projected or conformal (rebuilt at the next msa frame).
  void toggle_charts() {
    device.wait_idle();
    // K cycles the charts: static projection, static conformal, per-frame perspective (MSA-P),
    // per-frame orthographic (MSA-O).
    renderer.set_msa_charts(msa::Parametrization((uint32_t(renderer.msa_charts()) + 1) % 4));
  }
  void set_compare_mode(const std::string& name) {
    const std::string problem = renderer.mode_problem(name);
    if (problem.empty()) compare_mode = name;
    message(problem);
  }
  // B: the split view on or off; its right mode is the one after this one unless one was chosen.
  void toggle_split() {
    split = !split;
    if (split && compare_mode.empty()) {
      const auto& modes = renderer.modes();
      const auto it = std::find(modes.begin(), modes.end(), mode);
      compare_mode = (it == modes.end() || it + 1 == modes.end()) ? modes.front() : *(it + 1);
    }
  }
  void next_mode() {
    const auto& modes = renderer.modes();
    const auto it = std::find(modes.begin(), modes.end(), mode);
    mode = (it == modes.end() || it + 1 == modes.end()) ? modes.front() : *(it + 1);
  }
  void copy_camera() {
    const std::string line = camera_line(camera.camera());
    glfwSetClipboardString(window.get(), line.c_str());
    std::cout << line << std::endl;
    report.camera_lines.push_back(line);
  }
  // This view at width x height through the same renderer (no panels), as PFM or PNG.
  void render_at(uint32_t width, uint32_t height, const std::string& path) {
    check_render_size(width, height);
    OutputFiles files;
    for (const std::string& in : inputs) files.input(in);
    files.output(path, "render", kImageExtensions);
    device.wait_idle();
    const VkExtent2D window_extent = renderer.extent();
    renderer.resize({width, height});
    vk::GpuTimer timer(device, 8);
    timer.submit_and_wait([&](VkCommandBuffer cmd) { renderer.record(cmd, camera.camera(), mode, timer); });
    std::vector<float> rgba(size_t(width) * height * 4);
    vk::read_image(device, renderer.display(), sizeof(float) * 4, std::as_writable_bytes(std::span(rgba)));
    renderer.resize(window_extent);
    io::FloatImage image;
    image.width = width;
    image.height = height;
    image.channels = 3;
    for (size_t i = 0; i < rgba.size(); i += 4) image.pixels.insert(image.pixels.end(), {rgba[i], rgba[i + 1], rgba[i + 2]});
    files.write(path, [&](const std::string& file) { io::write_image(file, image); });
    files.commit();
    report.files_written.push_back(path);
  }
  void request_screenshot(const std::string& path) {
    check_output(path, "screenshot", {".png"}, inputs);
    capture_path = path;
  }
  void on_key(const KeyPress& key) {
    if (camera_key(camera, key, aspect())) return;
    switch (key.key) {
      case GLFW_KEY_M: next_mode(); break;
      case GLFW_KEY_B: toggle_split(); break;
      case GLFW_KEY_T: next_amortization(); break;
      case GLFW_KEY_K: toggle_charts(); break;
      case GLFW_KEY_L: set_shadows(!renderer.shadows()); break;
      case GLFW_KEY_H: show_ui = !show_ui; break;
      case GLFW_KEY_C: copy_camera(); break;
      case GLFW_KEY_P:
        try {
          request_screenshot("prismoid-screenshot-" + std::to_string(++screenshot_count) + ".png");
        } catch (const InputError& e) {
          message(e.what());
        }
        break;
      case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window.get(), GLFW_TRUE); break;
      default: break;
    }
  }
  void run(const ScriptCommand& c) {
    const auto& a = c.args;
    const auto whole = [&](size_t i) { return parse_uint(c.verb, a.at(i)); };
    if (c.verb == "key") on_key(key_from_name(a[0]));
    else if (c.verb == "mode") set_mode(a[0]);
    else if (c.verb == "shadows") set_shadows(script_on_off(c));
    else if (c.verb == "compare") {
      if (a[0] != "split" && a[0] != "off") throw std::invalid_argument("compare takes split or off in the surface window");
      if ((a[0] == "split") != split) toggle_split();
    } else if (c.verb == "compare-mode") set_compare_mode(a[0]);
    else if (run_camera_command(camera, c, swapchain.extent(), bounds)) {
    } else if (c.verb == "ui") show_ui = script_on_off(c);
    else if (c.verb == "screenshot") request_screenshot(a[0]);
    else if (c.verb == "render") render_at(whole(0), whole(1), a[2]);
    else if (c.verb == "print-camera") copy_camera();
    else if (c.verb == "resize") resize_window(window, whole(0), whole(1));
    else if (c.verb == "close") glfwSetWindowShouldClose(window.get(), GLFW_TRUE);
    else message(c.where + ": " + c.verb + " is not available in the surface window");
  }
};

// The panel: the mode, each pass's GPU time, the scene.
void draw_surface_panel(SurfaceSession& s) {
  ImGui::SetNextWindowPos(ImVec2(10.0f, 10.0f), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.8f);
  if (!ImGui::Begin("Surface", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::End();
    return;
  }
  ImGui::Text("%s", s.report.device_name.c_str());
  ImGui::Text("%s: %u triangles, %u emissive", s.renderer.scene().name.c_str(), s.renderer.gpu_scene().triangle_count,
              s.renderer.gpu_scene().emitter_count);
  ImGui::Separator();
  ImGui::TextUnformatted("Mode (M cycles)");
  for (const std::string& m : s.renderer.modes()) {
    if (ImGui::RadioButton(m.c_str(), s.mode == m)) s.set_mode(m);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", std::string(surface::find_surface_mode(m)->summary).c_str());
  }
  if (s.renderer.can_shadow()) {
    bool shadows = s.renderer.shadows();
    if (ImGui::Checkbox("ray-traced shadows (L)", &shadows)) s.set_shadows(shadows);
  } else {
    ImGui::TextDisabled("no shadows: the device has no ray tracing");
  }
  const uint32_t knobs = surface::find_surface_mode(s.mode)->backend->tuning;
  if (knobs & surface::kTuneAmortize) {
    const uint32_t n = s.renderer.msa_amortization();
    if (n == 0)
      ImGui::Text("%s shades every moved frame (T: amortize)", s.mode.c_str());
    else
      ImGui::Text("%s shades every %u frames while moving (T)", s.mode.c_str(), n);
  }
  if (knobs & surface::kTuneCharts)
    ImGui::Text("meshlet charts: %s (K)", msa::parametrization_name(s.renderer.msa_charts()));
  bool split = s.split;
  if (ImGui::Checkbox("split view (B)", &split)) s.toggle_split();
  if (s.split) {
    ImGui::SameLine();
    if (ImGui::BeginCombo("right", s.compare_mode.c_str())) {
      for (const std::string& m : s.renderer.modes())
        if (ImGui::Selectable(m.c_str(), m == s.compare_mode)) s.set_compare_mode(m);
      ImGui::EndCombo();
    }
  }
  ImGui::Separator();
  if (s.split) ImGui::Text("left: %s", s.mode.c_str());
  double total = 0.0;
  for (const auto& p : s.passes) {
    ImGui::Text("%s %.3f ms", p.name.c_str(), p.gpu_ms);
    total += p.gpu_ms;
  }
  if (s.split) {
    ImGui::Text("right: %s", s.compare_mode.c_str());
    for (const auto& p : s.compare_passes) ImGui::Text("%s %.3f ms", p.name.c_str(), p.gpu_ms);
  }
  ImGui::Text("GPU total %.3f ms, frame (CPU) %.2f ms", total, s.cpu_frame_ms);
  ImGui::Text("shaded %llu %s", static_cast<unsigned long long>(s.counts.shaded), s.counts.shaded_what.c_str());
  if (s.counts.mode_bytes) ImGui::Text("%s memory %.2f MiB", s.mode.c_str(), double(s.counts.mode_bytes) / (1024.0 * 1024.0));
  if (!s.counts.detail.empty()) ImGui::TextWrapped("%s", s.counts.detail.c_str());
  if (ImGui::TreeNode("Frame plan")) {  // the planner's passes for this scene and mode, each with why
    const frame::FramePlan& plan = s.renderer.last_plan();
    for (const frame::PlannedPass& p : plan.passes)
      ImGui::TextWrapped("%s (%s): %s", p.name.c_str(), frame::pass_kind_text(p.kind), p.reason.c_str());
    for (const frame::SkippedPass& p : plan.skipped) ImGui::TextWrapped("%s: skipped, %s", p.name.c_str(), p.reason.c_str());
    ImGui::TreePop();
  }
  if (ImGui::Button("Fit (R)")) s.camera.reset(s.aspect());
  ImGui::SameLine();
  if (ImGui::Button("Copy camera (C)")) s.copy_camera();
  if (!s.panel_message.empty()) ImGui::TextWrapped("%s", s.panel_message.c_str());
  ImGui::End();
}

// Columns [x0, x1) of `source` to the same columns of the swapchain image (the whole of it, or
// one half of the split view); `first` moves the target into TRANSFER_DST first.
void blit_to_swapchain(VkCommandBuffer cmd, const vk::Image& source, VkImage target, VkExtent2D extent, uint32_t x0, uint32_t x1, bool first) {
  if (first)
    vk::image_barrier(cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT,
                      VK_ACCESS_2_NONE, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  VkImageBlit region{};
  region.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.dstSubresource = region.srcSubresource;
  region.srcOffsets[0] = {int32_t(x0), 0, 0};
  region.srcOffsets[1] = {int32_t(x1), int32_t(source.extent().height), 1};
  region.dstOffsets[0] = {int32_t(x0), 0, 0};
  region.dstOffsets[1] = {int32_t(x1), int32_t(extent.height), 1};
  vkCmdBlitImage(cmd, source.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region,
                 VK_FILTER_NEAREST);
}

// The surface window's content in the shared frame loop: the SurfaceRenderer's frame of the
// chosen mode blitted to the swapchain, and the surface panel.
class SurfaceWindow final : public WindowContent {
 public:
  SurfaceWindow(SurfaceSession& s, const std::vector<ScriptCommand>& script) : s_(s), script_(script) {}

  CameraController& camera() override { return s_.camera; }
  bool show_ui() const override { return s_.show_ui; }
  void run_due() override {
    for (; next_command_ < script_.size() && script_[next_command_].frame <= frame_index_; ++next_command_) {
      try {
        s_.run(script_[next_command_]);
      } catch (const std::exception& e) {  // whatever a command meets, the window goes on
        s_.message(script_[next_command_].where + ": " + e.what());
      }
    }
  }
  void frame_started(double cpu_frame_ms) override { s_.cpu_frame_ms = cpu_frame_ms; }
  void on_key(const KeyPress& key) override { s_.on_key(key); }
  void frame_finished(std::vector<vk::PassTiming> passes, bool last) override {
    // Split view: the left mode's passes, then the right one's, then the blits.
    s_.compare_passes.clear();
    if (s_.split && s_.left_passes < passes.size()) {
      s_.compare_passes.assign(passes.begin() + std::ptrdiff_t(s_.left_passes), passes.end());
      passes.resize(s_.left_passes);
    }
    s_.passes = std::move(passes);
    if (!last) s_.counts = s_.renderer.read_counts();
  }
  std::string timings_line() const override {
    std::ostringstream title;
    title << "Prismoid - " << s_.report.device_name << " - " << s_.mode;
    for (const auto& t : s_.passes) title << " " << t.name << " " << t.gpu_ms << " ms";
    return title.str();
  }
  void draw_ui() override {
    if (s_.show_ui) draw_surface_panel(s_);
  }
  void prepare_frame(VkExtent2D extent) override { s_.renderer.resize(extent); }
  void record(VkCommandBuffer cmd, vk::GpuTimer& timer, VkImage target, VkExtent2D extent) override {
    const size_t first = timer.recorded().size();
    s_.renderer.record(cmd, s_.camera.camera(), s_.mode, timer);
    s_.left_passes = timer.recorded().size() - first;
    if (!s_.split || s_.compare_mode.empty()) {
      vk::ScopedPass pass(timer, cmd, "present-blit");
      blit_to_swapchain(cmd, s_.renderer.display(), target, extent, 0, extent.width, true);
      return;
    }
    // The left half now: the right mode may share the left one's backend and image.
    const uint32_t half = extent.width / 2;
    blit_to_swapchain(cmd, s_.renderer.display(), target, extent, 0, half, true);
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT);
    s_.renderer.record(cmd, s_.camera.camera(), s_.compare_mode, timer);
    vk::ScopedPass pass(timer, cmd, "present-blit");
    blit_to_swapchain(cmd, s_.renderer.display(), target, extent, half, extent.width, false);
  }
  std::optional<std::string> take_capture() override { return std::exchange(s_.capture_path, std::nullopt); }
  void capture_failed(const std::string& message) override { s_.message(message); }
  uint32_t& frame_index() override { return frame_index_; }
  const std::vector<std::string>& inputs() const override { return s_.inputs; }

 private:
  SurfaceSession& s_;
  const std::vector<ScriptCommand>& script_;
  size_t next_command_ = 0;
  uint32_t frame_index_ = 0;
};

}  // namespace

ViewerReport run_surface_viewer(const SurfaceScene& scene, const ViewerOptions& options) {
  const TerminateSignals signals;
  PresentingDevice presenting(options.validation, options.device_index);
  const vk::Instance& instance = presenting.instance;
  const vk::DeviceCapabilities& caps = presenting.caps;
  vk::Device& device = presenting.device;

  Window window(options.width, options.height, "Prismoid");
  Surface surface(instance.get(), window.get());
  vk::Swapchain swapchain(device, surface.get(), window.framebuffer_extent());
  surface::SurfaceRenderer renderer(device, scene);
  ImGuiLayer ui(device, window.get(), swapchain);
  SwapchainCapture capture(device);

  ViewerReport report;
  report.device_name = caps.name;
  const Bounds bounds = bounds_of(scene);
  SurfaceSession s{window, device, swapchain, renderer,
                   options.camera ? CameraController(bounds, *options.camera) : CameraController(bounds, scene.camera),
                   bounds, report, renderer.modes().front()};
  s.show_ui = options.show_ui;
  s.inputs = options.inputs;
  if (!options.mode.empty()) {
    if (const std::string problem = renderer.mode_problem(options.mode); !problem.empty()) throw InputError("--mode " + options.mode, problem);
    s.mode = options.mode;
  }

  SurfaceWindow content(s, options.script);
  WindowParts parts{window, device, swapchain, ui, capture};
  run_window_loop(parts, content, options, report);

  report.last_frame.frame.device = caps.name;
  report.last_frame.frame.passes = s.passes;
  report.last_frame.report().counted = true;
  report.last_frame.report().fragments = s.counts.shaded;
  report.camera = s.camera.camera();
  report.mode = s.mode;
  report.msa_amortization = s.renderer.msa_amortization();
  report.msa_charts = msa::parametrization_name(s.renderer.msa_charts());
  report.compare_mode = s.split ? s.compare_mode : std::string();
  report.compare_passes = s.compare_passes;
  report.validation_messages = instance.validation_log().count();
  return report;
}

}  // namespace prismoid::app
