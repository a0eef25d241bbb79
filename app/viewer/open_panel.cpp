// The panel's Data section and the load-error popup.
#include "app/viewer/open_panel.hpp"
#include "scene/tet_mesh.hpp"

#include <imgui.h>

#include <cmath>
#include <cstdio>

namespace prismoid::app {

namespace {

// The popup's identity; its title (before ###) changes with what failed.
constexpr const char* kErrorPopupId = "###prismoid-error";

void draw_datasets(const ViewState& state, DataRequests& requests) {
  for (size_t i = 0; i < state.datasets.size(); ++i) {
    const Dataset& d = state.datasets[i];
    ImGui::PushID(int(i));
    bool visible = d.visible;
    if (ImGui::Checkbox("##visible", &visible)) requests.show = std::make_pair(i, visible);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("show or hide");
    ImGui::SameLine();
    if (ImGui::RadioButton("##active", state.active == i)) requests.make_active = i;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("active: the transfer function uses its range");
    ImGui::SameLine();
    ImGui::TextWrapped("%s (%zu cells)", d.name.c_str(), d.mesh ? d.mesh->tets.size() : size_t(0));
    ImGui::PopID();
  }
}

void draw_progress(const LoadStatus& load, DataRequests& requests) {
  // An unknown fraction (TetGen) sweeps back and forth, so the bar still shows the work is alive.
  const float shown = load.fraction >= 0.0 ? float(load.fraction) : float(0.5 + 0.5 * std::sin(2.0 * load.seconds));
  const std::string queued = load.queued ? " (" + std::to_string(load.queued) + " more queued)" : "";
  ImGui::TextWrapped("loading %s%s: %s, %.1f s", load.label.c_str(), queued.c_str(), load.stage.c_str(), load.seconds);
  char overlay[32];
  if (load.fraction >= 0.0) std::snprintf(overlay, sizeof overlay, "%d%%", int(100.0 * load.fraction + 0.5));
  else std::snprintf(overlay, sizeof overlay, "working");
  ImGui::ProgressBar(shown, ImVec2(-80.0f, 0.0f), overlay);
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) requests.cancel = true;
}

// The active dataset's time steps: a slider over them, first / back / play / forward / last, and
// whether the colour range follows each step.
void draw_time(const ViewState& state, const DataPanel& panel, DataRequests& requests) {
  const Dataset& d = state.dataset();
  const int last = int(d.times.size()) - 1;
  int step = int(d.step);
  ImGui::Text("time: step %d of %d, t = %g%s", step, last, d.times[d.step], panel.step_loading ? " (loading)" : "");
  if (ImGui::SliderInt("step", &step, 0, last)) requests.time_step = uint32_t(step);
  if (ImGui::Button("|<")) requests.time_step = 0u;
  ImGui::SameLine();
  if (ImGui::Button("<")) requests.time_step = uint32_t(step > 0 ? step - 1 : last);
  ImGui::SameLine();
  if (ImGui::Button(panel.playing ? "pause" : "play")) requests.play = !panel.playing;
  ImGui::SameLine();
  if (ImGui::Button(">")) requests.time_step = uint32_t(step < last ? step + 1 : 0);
  ImGui::SameLine();
  if (ImGui::Button(">|")) requests.time_step = uint32_t(last);
  bool compare = state.compare_step.has_value();
  if (ImGui::Checkbox("split: B at step", &compare)) requests.compare_step = compare ? std::optional<uint32_t>(d.step) : std::nullopt;
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the split view's right half (B) draws another step, so A | B compare two steps");
  if (state.compare_step) {
    int b = int(*state.compare_step);
    ImGui::SameLine();
    if (ImGui::SliderInt("##b-step", &b, 0, last)) requests.compare_step = uint32_t(b);
  }
  bool per_step = state.range_per_step;
  if (ImGui::Checkbox("colour range per step", &per_step)) requests.range_per_step = per_step;
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("off (as ParaView): the range stays while time moves, so a colour means one value at every step");
}

}  // namespace

void draw_data_section(const ViewState& state, DataPanel& panel, DataRequests& requests) {
  draw_datasets(state, requests);
  if (!state.datasets.empty() && !state.dataset().times.empty()) draw_time(state, panel, requests);
  if (panel.load.running) draw_progress(panel.load, requests);
  const bool entered = ImGui::InputTextWithHint("##path", "file, field:NAME, grid:NAME, ball:S", panel.path, sizeof panel.path,
                                                ImGuiInputTextFlags_EnterReturnsTrue);
  ImGui::SameLine();
  if ((ImGui::Button("Open") || entered) && panel.path[0] != '\0') requests.open.emplace_back(panel.path);
  ImGui::InputTextWithHint("array", "none", panel.array, sizeof panel.array);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the point or cell array to read (as --array); files can also be dropped on the window");
  requests.array = panel.array;
  if (!panel.recent.empty() && ImGui::TreeNode("Recent files")) {
    for (const RecentEntry& r : panel.recent) {
      if (!r.exists) ImGui::BeginDisabled();
      if (ImGui::Selectable(r.path.c_str())) requests.open.push_back(r.path);
      if (!r.exists) {
        ImGui::EndDisabled();
        if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("missing");
      }
    }
    ImGui::TreePop();
  }
}

void draw_load_error_popup(DataPanel& panel) {
  if (panel.show_error) {
    ImGui::OpenPopup(kErrorPopupId);
    panel.show_error = false;
  }
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(viewport->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
  ImGui::SetNextWindowSizeConstraints(ImVec2(200.0f, 0.0f), ImVec2(0.8f * viewport->WorkSize.x, 0.8f * viewport->WorkSize.y));
  if (ImGui::BeginPopupModal((panel.error_title + kErrorPopupId).c_str(), nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::PushTextWrapPos(0.6f * viewport->WorkSize.x);
    ImGui::TextUnformatted(panel.error.c_str());
    ImGui::PopTextWrapPos();
    if (ImGui::Button("OK") || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape))) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
}

}  // namespace prismoid::app
