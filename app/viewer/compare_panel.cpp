#include "app/viewer/compare_panel.hpp"

#include <imgui.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "app/common/volume_options.hpp"
#include "app/viewer/compare.hpp"
#include "renderer/volume/volume_backends.hpp"

namespace prismoid::app {

namespace {

double gpu_total(const std::vector<vk::PassTiming>& passes) {
  double total = 0.0;
  for (const auto& p : passes)
    if (std::isfinite(p.gpu_ms) && p.name != "present-blit" && p.name != "ui") total += p.gpu_ms;
  return total;
}

// A label with a dark box behind it, centred at (x, bottom - its height), over every window.
void label_at(float x, float bottom, const std::string& text) {
  ImDrawList* draw = ImGui::GetForegroundDrawList();
  const ImVec2 size = ImGui::CalcTextSize(text.c_str());
  const ImVec2 at(x - size.x / 2.0f, bottom - size.y - 6.0f);
  draw->AddRectFilled(ImVec2(at.x - 4.0f, at.y - 2.0f), ImVec2(at.x + size.x + 4.0f, at.y + size.y + 2.0f), IM_COL32(0, 0, 0, 170), 3.0f);
  draw->AddText(at, IM_COL32(255, 255, 255, 255), text.c_str());
}

std::string mode_label(const char* side, const std::string& mode, volume::Quantity q, double ms) {
  char text[160];
  std::snprintf(text, sizeof text, "%s: %s, %s  %.3f ms", side, mode.c_str(), quantity_name(q), ms);
  return text;
}

// The heat map's ramp (error_heat_map's: black, red, yellow, white in equal thirds) and its scale.
void draw_legend(double scale) {
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float w = 180.0f, h = 12.0f, third = w / 3.0f;
  const ImU32 stops[4] = {IM_COL32(0, 0, 0, 255), IM_COL32(255, 0, 0, 255), IM_COL32(255, 255, 0, 255), IM_COL32(255, 255, 255, 255)};
  ImDrawList* draw = ImGui::GetWindowDrawList();
  for (int i = 0; i < 3; ++i)
    draw->AddRectFilledMultiColor(ImVec2(at.x + third * float(i), at.y), ImVec2(at.x + third * float(i + 1), at.y + h), stops[i],
                                  stops[i + 1], stops[i + 1], stops[i]);
  ImGui::Dummy(ImVec2(w, h));
  ImGui::Text("0");
  ImGui::SameLine(w - 90.0f);
  ImGui::Text("%10.3g (max)", scale);
  ImGui::TextDisabled("magenta: NaN or infinite");
}

void draw_difference(const CompareStatus& status) {
  if (!status.error.empty()) {
    ImGui::TextWrapped("reference failed: %s", status.error.c_str());
    return;
  }
  if (status.computing) ImGui::Text("computing reference... %.0f s", status.computing_seconds);
  if (!status.last) return;
  const FrameComparison& c = *status.last;
  if (!status.heat_map_shown) ImGui::TextDisabled("last reference (an earlier view):");
  ImGui::Text("vs CPU reference, %s", c.channels.c_str());
  ImGui::Text("at %u x %u (long side <= %u)", c.width, c.height, kReferenceMaxSide);
  ImGui::Text("RMSE %.4g   max %.4g", c.error.rmse, c.error.max_abs);
  ImGui::Text("PSNR %.1f dB (peak %.3g)", c.error.psnr_db, c.peak);
  ImGui::Text("non-finite %zu   reference %.1f s", c.error.non_finite, status.reference_seconds);
  if (status.heat_map_shown) draw_legend(c.scale);
}

}  // namespace

void draw_compare_section(ViewState& state, PanelState& panel) {
  int mode = int(state.compare);
  const char* names[] = {"off", "split (A | B)", "difference vs reference"};
  if (ImGui::Combo("compare", &mode, names, 3)) panel.message = set_compare(state, CompareMode(mode));
  if (state.compare == CompareMode::Split) {
    if (ImGui::BeginCombo("B mode", state.compare_mode.c_str())) {
      for (const std::string& m : modes_for(state.dataset()))
        if (ImGui::Selectable(m.c_str(), m == state.compare_mode)) panel.message = set_compare_mode(state, m);
      ImGui::EndCombo();
    }
    const volume::Quantity current = state.compare_settings.resolve.quantity;
    if (ImGui::BeginCombo("B quantity", quantity_name(current))) {
      for (volume::Quantity q : quantities_for(state.dataset(), state.compare_mode))
        if (ImGui::Selectable(quantity_name(q), q == current)) panel.message = set_compare_quantity(state, q);
      ImGui::EndCombo();
    }
    const char* b_backend = frame::interval_backend_name(state.compare_settings.backend);
    if (ImGui::BeginCombo("B backend", b_backend)) {
      for (const volume::VolumeBackendInfo* info : volume::volume_backend_table()) {
        if (!info->gpu()) continue;
        const char* name = info->name.data();
        if (ImGui::Selectable(name, std::string(name) == b_backend)) panel.message = set_compare_backend(state, name);
      }
      ImGui::EndCombo();
    }
    ImGui::TextDisabled("left: A (the mode above), right: B; B shares A's transfer function");
  } else if (state.compare == CompareMode::Difference) {
    ImGui::TextWrapped("The mode above against the CPU double-precision reference, at the window's size scaled to at most %u "
                       "pixels a side; recomputed when the view rests for %.1f s.",
                       kReferenceMaxSide, kReferenceRestSeconds);
  }
}

void draw_compare_overlay(const CompareStatus& status, const ViewState& state, const FrameStats& stats) {
  if (state.compare == CompareMode::Off) return;
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  const float bottom = viewport->WorkPos.y + viewport->WorkSize.y;
  // Appended to the HUD window draw_hud began this frame.
  if (ImGui::Begin("HUD")) {
    ImGui::Separator();
    if (state.compare == CompareMode::Split) {
      ImGui::Text("B: %s, %s", status.b_mode.c_str(), quantity_name(status.b_quantity));
      for (const auto& p : status.b_passes) ImGui::Text("  %s %.3f ms", p.name.c_str(), p.gpu_ms);
      ImGui::Text("B GPU total %.3f ms", gpu_total(status.b_passes));
    } else {
      draw_difference(status);
    }
  }
  ImGui::End();
  if (state.compare == CompareMode::Split) {
    const float quarter = viewport->WorkSize.x / 4.0f;
    label_at(viewport->WorkPos.x + quarter, bottom, mode_label("A", state.mode, state.settings.resolve.quantity, gpu_total(stats.frame.passes)));
    label_at(viewport->WorkPos.x + 3.0f * quarter, bottom, mode_label("B", status.b_mode, status.b_quantity, gpu_total(status.b_passes)));
  } else if (status.computing) {
    char note[96];
    std::snprintf(note, sizeof note, "computing reference... %.0f s (showing the plain mode)", status.computing_seconds);
    label_at(viewport->WorkPos.x + viewport->WorkSize.x / 2.0f, bottom, note);
  } else if (status.heat_map_shown && status.last) {
    char note[128];
    std::snprintf(note, sizeof note, "error vs reference: RMSE %.3g, max %.3g", status.last->error.rmse, status.last->error.max_abs);
    label_at(viewport->WorkPos.x + viewport->WorkSize.x / 2.0f, bottom, note);
  }
}

}  // namespace prismoid::app
