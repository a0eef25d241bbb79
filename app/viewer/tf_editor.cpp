// The transfer-function section: presets, the opacity points on a plot over the colour map,
// the scalar range, and ParaView JSON import/export.
#include <imgui.h>

#include <algorithm>

#include "app/viewer/panels.hpp"
#include "app/viewer/tf_edit.hpp"

namespace prismoid::app {

namespace {

ImU32 color_at(const std::vector<volume::TfSample>& samples, double x) {
  const volume::TfSample s = volume::evaluate(samples, x);
  const glm::dvec3 c = glm::clamp(s.rgb, 0.0, 1.0);
  return ImGui::ColorConvertFloat4ToU32(ImVec4(float(c.r), float(c.g), float(c.b), 1.0f));
}

// The plot: the colour map as the background, the opacity function as a polyline with its
// points. Left click on empty space adds a point, left drag moves one, right click removes one.
void draw_opacity_plot(volume::TransferFunction& tf, PanelState& panel) {
  const ImVec2 size(ImGui::GetContentRegionAvail().x, 110.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("opacity plot", size, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const auto samples = volume::breakpoints(tf);
  constexpr int kStrips = 64;
  for (int i = 0; i < kStrips; ++i) {
    const float x0 = origin.x + size.x * float(i) / kStrips, x1 = origin.x + size.x * float(i + 1) / kStrips;
    draw->AddRectFilledMultiColor(ImVec2(x0, origin.y), ImVec2(x1, origin.y + size.y), color_at(samples, (i + 0.0) / kStrips),
                                  color_at(samples, (i + 1.0) / kStrips), color_at(samples, (i + 1.0) / kStrips),
                                  color_at(samples, (i + 0.0) / kStrips));
  }
  auto to_screen = [&](double x, double o) {
    return ImVec2(origin.x + float(x) * size.x, origin.y + (1.0f - float(o)) * size.y);
  };
  const ImU32 line = IM_COL32(0, 0, 0, 255), point = IM_COL32(255, 255, 255, 255);
  for (size_t i = 0; i + 1 < tf.opacity.size(); ++i)
    draw->AddLine(to_screen(tf.opacity[i].x, tf.opacity[i].opacity), to_screen(tf.opacity[i + 1].x, tf.opacity[i + 1].opacity), line, 2.0f);
  for (const auto& p : tf.opacity) {
    draw->AddCircleFilled(to_screen(p.x, p.opacity), 5.0f, point);
    draw->AddCircle(to_screen(p.x, p.opacity), 5.0f, line);
  }

  const ImVec2 mouse = ImGui::GetIO().MousePos;
  const double mx = double((mouse.x - origin.x) / size.x), mo = double(1.0f - (mouse.y - origin.y) / size.y);
  const double pick_radius = 8.0 / double(size.y);
  if (ImGui::IsItemClicked(ImGuiMouseButton_Left)) {
    const size_t hit = nearest_opacity_point(tf, mx, mo, pick_radius);
    panel.dragged_point = int(hit < tf.opacity.size() ? hit : add_opacity_point(tf, mx, mo));
  }
  if (ImGui::IsItemClicked(ImGuiMouseButton_Right)) {
    const size_t hit = nearest_opacity_point(tf, mx, mo, pick_radius);
    if (hit < tf.opacity.size()) remove_opacity_point(tf, hit);
    panel.dragged_point = -1;
  }
  if (panel.dragged_point >= 0 && ImGui::IsMouseDown(ImGuiMouseButton_Left) && size_t(panel.dragged_point) < tf.opacity.size())
    move_opacity_point(tf, size_t(panel.dragged_point), mx, mo);
  if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) panel.dragged_point = -1;
  ImGui::TextDisabled("click: add point, drag: move, right click: remove");
}

}  // namespace

void draw_tf_section(ViewState& state, PanelState& panel, UiRequests& requests) {
  volume::TransferFunction& tf = state.settings.resolve.transfer;
  if (ImGui::BeginCombo("preset", state.tf_preset.c_str())) {
    for (const auto& name : volume::preset_names())
      if (ImGui::Selectable(name.c_str(), name == state.tf_preset)) panel.message = set_preset(state, name);
    ImGui::EndCombo();
  }
  draw_opacity_plot(tf, panel);

  double range[2] = {tf.range_lo, tf.range_hi};
  if (ImGui::InputScalarN("range", ImGuiDataType_Double, range, 2, nullptr, nullptr, "%.6g", ImGuiInputTextFlags_EnterReturnsTrue)) {
    if (range[1] > range[0]) {
      tf.range_lo = range[0];
      tf.range_hi = range[1];
    } else {
      panel.message = "range: the upper end must be above the lower";
    }
  }
  if (ImGui::Button("range from data")) {
    tf.range_lo = state.dataset().scalar_lo;
    tf.range_hi = state.dataset().scalar_hi;
  }
  ImGui::InputText("file", panel.tf_path, sizeof panel.tf_path);
  if (ImGui::Button("import ParaView JSON")) requests.import_tf = std::string(panel.tf_path);
  ImGui::SameLine();
  if (ImGui::Button("export ParaView JSON")) requests.export_tf = std::string(panel.tf_path);
}

}  // namespace prismoid::app
