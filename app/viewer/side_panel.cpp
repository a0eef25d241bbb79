// The left-hand panel and its view (camera) section.
#include <imgui.h>

#include <algorithm>

#include "app/viewer/camera_line.hpp"
#include "app/viewer/compare_panel.hpp"
#include "app/viewer/panels.hpp"

namespace prismoid::app {

void draw_view_section(PanelState& panel, const CameraController& camera, UiRequests& requests) {
  if (ImGui::Button("reset (R)")) requests.reset_camera = true;
  ImGui::SameLine();
  bool flying = camera.flying();
  if (ImGui::Checkbox("fly (F)", &flying)) requests.toggle_fly = true;
  constexpr AxisView kViews[] = {AxisView::PlusX, AxisView::MinusX, AxisView::PlusY, AxisView::MinusY, AxisView::PlusZ, AxisView::MinusZ};
  for (AxisView v : kViews) {
    if (v != AxisView::PlusX) ImGui::SameLine();
    if (ImGui::Button(axis_view_name(v))) requests.axis_view = v;
  }
  if (ImGui::Button("copy camera (C)")) requests.copy_camera = true;
  ImGui::SameLine();
  if (ImGui::Button("apply pasted")) requests.apply_camera_line = std::string(panel.camera_text);
  ImGui::InputText("##camera", panel.camera_text, sizeof panel.camera_text);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", camera_line(camera.camera()).c_str());

  ImGui::InputText("##screenshot", panel.screenshot_path, sizeof panel.screenshot_path);
  ImGui::SameLine();
  if (ImGui::Button("screenshot (P)")) requests.screenshot = std::string(panel.screenshot_path);
  ImGui::InputInt2("size", panel.render_size);
  ImGui::InputText("##render", panel.render_path, sizeof panel.render_path);
  ImGui::SameLine();
  if (ImGui::Button("render at size")) {
    if (panel.render_size[0] > 0 && panel.render_size[1] > 0 && panel.render_size[0] <= 16384 && panel.render_size[1] <= 16384)
      requests.render = RenderRequest{uint32_t(panel.render_size[0]), uint32_t(panel.render_size[1]), panel.render_path};
    else
      panel.message = "render: each side must be between 1 and 16384 pixels";
  }
}

UiRequests draw_side_panel(ViewState& state, PanelState& panel, const FrameStats& stats, const CameraController& camera,
                           uint32_t max_tetlet_size) {
  UiRequests requests;
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(viewport->WorkPos, ImGuiCond_Once);
  // At most 45% of the window, so the volume stays in sight on small windows.
  ImGui::SetNextWindowSize(ImVec2(std::min(340.0f, 0.45f * viewport->WorkSize.x), viewport->WorkSize.y), ImGuiCond_Once);
  ImGui::SetNextWindowBgAlpha(0.85f);
  if (ImGui::Begin("Prismoid")) {
    ImGui::PushItemWidth(ImGui::GetWindowWidth() * 0.55f);  // room for the labels on the right
    if (!panel.message.empty()) {  // the last refusal or confirmation, where it is seen
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.85f, 0.4f, 1.0f));
      ImGui::TextWrapped("%s", panel.message.c_str());
      ImGui::PopStyleColor();
    }
    if (ImGui::CollapsingHeader("Data", ImGuiTreeNodeFlags_DefaultOpen)) draw_data_section(state, panel.data, requests.data);
    if (ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) draw_view_section(panel, camera, requests);
    if (ImGui::CollapsingHeader("Mode", ImGuiTreeNodeFlags_DefaultOpen)) draw_mode_section(state, panel, max_tetlet_size);
    if (state.settings.resolve.quantity == volume::Quantity::Color &&
        ImGui::CollapsingHeader("Transfer function", ImGuiTreeNodeFlags_DefaultOpen))
      draw_tf_section(state, panel, requests);
    if (ImGui::CollapsingHeader("Compare", ImGuiTreeNodeFlags_DefaultOpen)) draw_compare_section(state, panel);
    if (ImGui::CollapsingHeader("Frame plan", ImGuiTreeNodeFlags_DefaultOpen)) draw_frame_plan(state, stats);
    ImGui::PopItemWidth();
  }
  ImGui::End();
  draw_load_error_popup(panel.data);
  return requests;
}

}  // namespace prismoid::app
