// What keys, panel buttons and script commands do: one implementation each, so a scripted test
// exercises the same code a person does.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <unistd.h>

#include "app/common/cli_args.hpp"
#include "app/common/frame_image.hpp"
#include "app/common/output_files.hpp"
#include "app/common/volume_options.hpp"
#include "app/viewer/camera_line.hpp"
#include "app/viewer/compare.hpp"
#include "app/viewer/dataset_list.hpp"
#include "app/viewer/mouse_bindings.hpp"
#include "app/viewer/viewer_session.hpp"
#include "io/image_io.hpp"
#include "io/transfer_function_io.hpp"
#include "scene/input_error.hpp"

namespace prismoid::app {

namespace {

uint64_t resident_kib() {
  std::ifstream statm("/proc/self/statm");
  uint64_t pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * uint64_t(sysconf(_SC_PAGESIZE)) / 1024;
}

}  // namespace

bool script_on_off(const ScriptCommand& c, size_t index) {
  if (c.args.at(index) == "on") return true;
  if (c.args.at(index) == "off") return false;
  throw InputError(c.where, c.verb + " takes on or off");
}

namespace {

AxisView axis_from_name(const std::string& where, const std::string& name) {
  for (AxisView v : {AxisView::PlusX, AxisView::MinusX, AxisView::PlusY, AxisView::MinusY, AxisView::PlusZ, AxisView::MinusZ})
    if (name == axis_view_name(v)) return v;
  throw InputError(where, "view takes +X, -X, +Y, -Y, +Z or -Z");
}

}  // namespace

KeyPress key_from_name(const std::string& name) {
  KeyPress k;
  std::string key = name;
  if (key.rfind("shift+", 0) == 0) {
    k.mods = GLFW_MOD_SHIFT;
    key = key.substr(6);
  }
  if (key == "Escape") k.key = GLFW_KEY_ESCAPE;
  else if (key.size() == 1 && key[0] >= 'A' && key[0] <= 'Z') k.key = GLFW_KEY_A + (key[0] - 'A');
  else if (key.size() == 1 && key[0] >= '0' && key[0] <= '9') k.key = GLFW_KEY_0 + (key[0] - '0');
  else throw InputError("key " + name, "names a letter A-Z, a digit or Escape, optionally after shift+");
  return k;
}

double ViewerSession::aspect() const {
  const VkExtent2D e = swapchain.extent();
  return e.height ? double(e.width) / double(e.height) : 1.0;
}

void ViewerSession::message(const std::string& text) {
  if (text.empty()) return;
  panel.message = text;
  report.messages.push_back(text);
  std::cerr << "prismoid: " << text << "\n";
}

void ViewerSession::failed(const std::string& title, const std::string& text) {
  message(text);
  panel.data.error = text;
  panel.data.error_title = title;
  panel.data.show_error = true;
  report.error_popups.push_back(title + ": " + text);
}

void ViewerSession::attempt(const std::string& title, const std::string& where, const std::function<void()>& action) {
  try {
    action();
  } catch (const std::exception& e) {  // what the user asked for failed; the window goes on
    failed(title, (where.empty() ? std::string() : where + ": ") + e.what());
  }
}

void ViewerSession::copy_camera() {
  const std::string line = camera_line(camera.camera());
  glfwSetClipboardString(window.get(), line.c_str());
  std::snprintf(panel.camera_text, sizeof panel.camera_text, "%s", line.c_str());
  std::cout << line << std::endl;
  report.camera_lines.push_back(line);
}

void ViewerSession::render_at(uint32_t width, uint32_t height, const std::string& path) {
  // The same path as `prismoid render`: an offscreen frame of this camera and these settings,
  // its size within render's --size bounds and its file checked before any work.
  check_render_size(width, height);
  OutputFiles files;
  for (const std::string& in : inputs) files.input(in);
  files.output(path, "render", kImageExtensions);
  device.wait_idle();
  const frame::OffscreenFrame frame = renderer.render_offscreen(camera.camera(), state.settings, {width, height});
  const io::FloatImage image = frame_image(frame, path, state.settings.resolve.quantity == volume::Quantity::Color);
  files.write(path, [&](const std::string& file) { io::write_image(file, image); });
  files.commit();
  report.files_written.push_back(path);
  panel.message = "wrote " + path;
}

void ViewerSession::request_screenshot(const std::string& path) {
  check_output(path, "screenshot", {".png"}, inputs);
  capture_path = path;
}

void ViewerSession::import_transfer_function(const std::string& path) {
  volume::ResolveSettings& r = state.settings.resolve;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw InputError(path, "is a folder, not a ParaView colour-map file");
  inputs.push_back(path);
  volume::TransferFunction read = io::read_paraview_colormap(path);
  read.range_lo = r.transfer.range_lo;
  read.range_hi = r.transfer.range_hi;
  read.density_scale = r.transfer.density_scale;
  r.transfer = std::move(read);
  state.tf_preset = r.transfer.name;
  panel.message = "imported " + path;
}

void ViewerSession::export_transfer_function(const std::string& path) {
  OutputFiles files;
  for (const std::string& in : inputs) files.input(in);
  files.output(path, "tf-export", {".json"});
  files.write(path, [&](const std::string& file) { io::write_paraview_colormap(file, state.settings.resolve.transfer); });
  files.commit();
  report.files_written.push_back(path);
  panel.message = "wrote " + path;
}

void check_render_size(uint32_t width, uint32_t height) {
  if (width == 0 || height == 0 || width > 16384 || height > 16384) throw InputError("render", "each side must be between 1 and 16384 pixels");
}

void resize_window(Window& window, uint32_t width, uint32_t height) {
  // X ends the process on a zero size (BadValue), so it never reaches the window system.
  if (width == 0 || height == 0 || width > 16384 || height > 16384) throw InputError("resize", "each side must be between 1 and 16384 pixels");
  glfwSetWindowSize(window.get(), int(width), int(height));
}

bool camera_key(CameraController& camera, const KeyPress& key, double aspect) {
  const bool shift = (key.mods & GLFW_MOD_SHIFT) != 0;
  switch (key.key) {
    case GLFW_KEY_R: camera.reset(aspect); return true;
    case GLFW_KEY_F: camera.set_flying(!camera.flying()); return true;
    case GLFW_KEY_X: camera.axis_view(shift ? AxisView::MinusX : AxisView::PlusX, aspect); return true;
    case GLFW_KEY_Y: camera.axis_view(shift ? AxisView::MinusY : AxisView::PlusY, aspect); return true;
    case GLFW_KEY_Z: camera.axis_view(shift ? AxisView::MinusZ : AxisView::PlusZ, aspect); return true;
    default: return false;
  }
}

bool run_camera_command(CameraController& camera, const ScriptCommand& c, VkExtent2D extent, const Bounds& bounds) {
  const auto& a = c.args;
  const auto number = [&](size_t i) { return parse_double(c.verb, a.at(i)); };
  const glm::dvec2 viewport(extent.width, extent.height);
  const double aspect = extent.height ? double(extent.width) / double(extent.height) : 1.0;
  if (c.verb == "camera") camera.set_camera(camera_from_line(c.rest, bounds));
  else if (c.verb == "view") camera.axis_view(axis_from_name(c.where, a[0]), aspect);
  else if (c.verb == "reset") camera.reset(aspect);
  else if (c.verb == "rotate") camera.rotate({number(0), number(1)}, viewport);
  else if (c.verb == "pan") camera.pan({number(0), number(1)}, viewport);
  else if (c.verb == "zoom") camera.zoom(number(0));
  else if (c.verb == "drag") {  // what the mouse bindings make of a drag with these buttons
    MouseButtons b;
    for (size_t i = 2; i < a.size(); ++i) {
      if (a[i] == "left") b.left = true;
      else if (a[i] == "middle") b.middle = true;
      else if (a[i] == "right") b.right = true;
      else if (a[i] == "shift") b.shift = true;
      else throw InputError(c.where, "drag DX DY takes buttons left, middle, right and shift");
    }
    if (const auto gesture = drag_gesture(b, camera.flying())) apply_drag(camera, *gesture, {number(0), number(1)}, viewport);
  } else if (c.verb == "fly") camera.set_flying(script_on_off(c));
  else if (c.verb == "fly-move") camera.fly_move({number(0), number(1), number(2)}, number(3));
  else if (c.verb == "fly-look") camera.fly_look({number(0), number(1)}, viewport);
  else return false;
  return true;
}

void ViewerSession::on_key(const KeyPress& key) {
  if (camera_key(camera, key, aspect())) return;
  switch (key.key) {
    case GLFW_KEY_H: state.show_ui = !state.show_ui; break;
    case GLFW_KEY_C: copy_camera(); break;
    case GLFW_KEY_P:
      attempt("Could not write", "", [&] { request_screenshot("prismoid-screenshot-" + std::to_string(++screenshot_count) + ".png"); });
      break;
    case GLFW_KEY_ESCAPE: glfwSetWindowShouldClose(window.get(), GLFW_TRUE); break;
    default: break;
  }
}

void ViewerSession::apply(const UiRequests& r) {
  apply_data_requests(*this, r.data);
  if (r.reset_camera) camera.reset(aspect());
  if (r.toggle_fly) camera.set_flying(!camera.flying());
  if (r.axis_view) camera.axis_view(*r.axis_view, aspect());
  if (r.copy_camera) copy_camera();
  if (r.apply_camera_line) {
    try {
      camera.set_camera(camera_from_line(*r.apply_camera_line, state.drawn().bounds));
    } catch (const InputError& e) {
      message(e.what());
    }
  }
  if (r.screenshot) attempt("Could not write", "", [&] { request_screenshot(*r.screenshot); });
  if (r.render) attempt("Could not write", "", [&] { render_at(r.render->width, r.render->height, r.render->path); });
  if (r.import_tf) attempt("Could not open", "", [&] { import_transfer_function(*r.import_tf); });
  if (r.export_tf) attempt("Could not write", "", [&] { export_transfer_function(*r.export_tf); });
}

void ViewerSession::run(const ScriptCommand& c) {
  const auto& a = c.args;
  const auto number = [&](size_t i) { return parse_double(c.verb, a.at(i)); };
  const auto whole = [&](size_t i) { return parse_uint(c.verb, a.at(i)); };
  volume::ResolveSettings& r = state.settings.resolve;
  const glm::dvec2 viewport(swapchain.extent().width, swapchain.extent().height);
  if (c.verb == "key") on_key(key_from_name(a[0]));
  else if (c.verb == "mode") message(set_mode(state, a[0]));
  else if (c.verb == "quantity") message(set_quantity(state, quantity_of_name(a[0])));
  else if (c.verb == "tf") {
    const auto names = volume::preset_names();
    if (std::find(names.begin(), names.end(), a[0]) != names.end()) message(set_preset(state, a[0]));
    else attempt("Could not open", c.where, [&] { import_transfer_function(a[0]); });
  } else if (c.verb == "tf-range") {
    if (a.size() == 1 && a[0] == "data") {
      r.transfer.range_lo = state.dataset().scalar_lo;
      r.transfer.range_hi = state.dataset().scalar_hi;
    } else if (a.size() == 2 && number(1) > number(0)) {
      r.transfer.range_lo = number(0);
      r.transfer.range_hi = number(1);
    } else {
      throw InputError(c.where, "tf-range takes LO HI with HI > LO, or data");
    }
  } else if (c.verb == "tf-export") {
    attempt("Could not write", c.where, [&] { export_transfer_function(a[0]); });
  } else if (c.verb == "tetlet-size") r.tetlet_size = whole(0);
  else if (c.verb == "shared-vertices") {
    const bool on = script_on_off(c);
    const std::string problem = shared_vertices_problem(state);
    if (on && !problem.empty()) message("shared-vertices: " + problem);
    else r.shared_vertices = on;
  } else if (c.verb == "preintegration-size") r.preintegration_size = whole(0);
  else if (c.verb == "march-step") r.march.step = number(0);
  else if (c.verb == "density-scale") (r.quantity == volume::Quantity::Color ? r.transfer.density_scale : r.march.density_scale) = number(0);
  else if (run_camera_command(camera, c, swapchain.extent(), state.drawn().bounds)) {
  }
  else if (c.verb == "ui") state.show_ui = script_on_off(c);
  else if (c.verb == "screenshot") attempt("Could not write", c.where, [&] { request_screenshot(a[0]); });
  else if (c.verb == "render") attempt("Could not write", c.where, [&] { render_at(whole(0), whole(1), a[2]); });
  else if (c.verb == "print-camera") copy_camera();
  else if (c.verb == "resize") attempt("Refused", c.where, [&] { resize_window(window, whole(0), whole(1)); });
  else if (c.verb == "iconify") glfwIconifyWindow(window.get());
  else if (c.verb == "restore") glfwRestoreWindow(window.get());
  else if (c.verb == "close") glfwSetWindowShouldClose(window.get(), GLFW_TRUE);
  else if (c.verb == "rss") report.resident_kib.emplace_back(frame_index, resident_kib());
  else if (c.verb == "open") open_datasets(*this, {a[0]}, a.size() > 1 ? a[1] : std::string());
  else if (c.verb == "drop") window.queue_drop(a);
  else if (c.verb == "wait-load") begin_script_wait(*this, a.empty() ? 120.0 : number(0));
  else if (c.verb == "cancel-load") cancel_loads(*this);
  else if (c.verb == "time-step") message(go_to_step(*this, whole(0)));
  else if (c.verb == "play") message(set_playing(*this, script_on_off(c)));
  else if (c.verb == "wait-step") {
    time.waiting_for = whole(0);
    begin_script_wait(*this, a.size() > 1 ? number(1) : 120.0);
  }
  else if (c.verb == "range-per-step") state.range_per_step = script_on_off(c);
  else if (c.verb == "compare-step") message(set_compare_step(*this, a[0] == "off" ? std::nullopt : std::optional<uint32_t>(whole(0))));
  else if (c.verb == "show") message(show_dataset(state, whole(0), script_on_off(c, 1)));
  else if (c.verb == "active") message(set_active(state, whole(0)));
  else if (c.verb == "compare") {
    const auto mode = compare_mode_of_name(a[0]);
    if (!mode) throw InputError(c.where, "compare takes off, split or difference");
    message(set_compare(state, *mode));
  } else if (c.verb == "compare-mode") message(set_compare_mode(state, a[0]));
  else if (c.verb == "compare-quantity") message(set_compare_quantity(state, quantity_of_name(a[0])));
  else if (c.verb == "backend") message(set_backend(state, a[0]));
  else if (c.verb == "compare-backend") message(set_compare_backend(state, a[0]));
  else if (c.verb == "wait-reference") {
    if (a.size() > 1) throw InputError(c.where, "wait-reference takes at most a number of seconds");
    const double seconds = a.empty() ? 300.0 : number(0);
    reference_deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                                 std::chrono::duration<double>(seconds));
  } else {
    message(c.where + ": " + c.verb + " is for the surface window");
  }
}

}  // namespace prismoid::app
