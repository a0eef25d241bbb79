// The mode section of the side panel and the frame plan under it.
#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "app/common/volume_options.hpp"
#include "app/viewer/compare.hpp"
#include "app/viewer/panels.hpp"
#include "renderer/volume/volume_backends.hpp"

namespace prismoid::app {

std::string pass_reason(const std::string& pass, const frame::FramePlan& plan) {
  for (const frame::PlannedPass& p : plan.passes)
    if (p.name == pass) return p.reason;
  // The window's own passes, recorded after the planned frame.
  if (pass == "present-blit") return "the display image into the window";
  if (pass == "ui") return "the panels";
  return "";
}

namespace {

template <typename T>
bool combo(const char* label, const std::vector<T>& items, const T& current, T& chosen, const char* (*name)(const T&)) {
  bool changed = false;
  if (ImGui::BeginCombo(label, name(current))) {
    for (const T& item : items)
      if (ImGui::Selectable(name(item), item == current)) {
        chosen = item;
        changed = true;
      }
    ImGui::EndCombo();
  }
  return changed;
}

const char* string_name(const std::string& s) { return s.c_str(); }
const char* quantity_label(const volume::Quantity& q) { return quantity_name(q); }

void draw_frame_plan_rows(const FrameStats& stats) {
  const frame::FrameReport& report = stats.report();
  ImGui::TextWrapped("ordering: %s", report.ordering.c_str());
  auto dim = [](const std::string& text) {
    ImGui::Indent();
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
    ImGui::TextWrapped("%s", text.c_str());
    ImGui::PopStyleColor();
    ImGui::Unindent();
  };
  auto row = [&](const std::string& name, double ms, const char* where) {
    if (std::isfinite(ms)) ImGui::Text("%s%s  %.3f ms", name.c_str(), where, ms);
    else ImGui::Text("%s%s", name.c_str(), where);
    const std::string why = pass_reason(name, report.plan);
    if (!why.empty()) dim(why);
  };
  for (const auto& p : report.cpu_passes) row(p.name, p.gpu_ms, " (CPU)");
  for (const auto& p : stats.frame.passes) row(p.name, p.gpu_ms, "");
  for (const auto& p : report.plan.skipped) dim(p.name + ": skipped, " + p.reason);
}

}  // namespace

void draw_mode_section(ViewState& state, PanelState& panel, uint32_t max_tetlet_size) {
  std::string mode = state.mode;
  if (combo<std::string>("mode", modes_for(state.dataset()), state.mode, mode, string_name)) panel.message = set_mode(state, mode);
  volume::Quantity quantity = state.settings.resolve.quantity;
  if (combo<volume::Quantity>("quantity", quantities_for(state.dataset(), state.mode), quantity, quantity, quantity_label))
    panel.message = set_quantity(state, quantity);

  const char* backend = frame::interval_backend_name(state.settings.backend);
  if (ImGui::BeginCombo("backend", backend)) {
    for (const volume::VolumeBackendInfo* info : volume::volume_backend_table()) {
      if (!info->gpu()) continue;
      const char* name = info->name.data();
      if (ImGui::Selectable(name, std::string(name) == backend)) panel.message = set_backend(state, name);
    }
    ImGui::EndCombo();
  }
  if (!state.settings.backend_reason.empty()) ImGui::TextDisabled("%s", state.settings.backend_reason.c_str());

  volume::ResolveSettings& r = state.settings.resolve;
  int tetlet = int(r.tetlet_size);
  std::vector<uint32_t> sizes;
  for (uint32_t s : volume::kTetletSizes)
    if (s <= max_tetlet_size) sizes.push_back(s);
  if (ImGui::BeginCombo("tetlet size", std::to_string(tetlet).c_str())) {
    for (uint32_t s : sizes)
      if (ImGui::Selectable(std::to_string(s).c_str(), s == r.tetlet_size)) {
        r.tetlet_size = s;
        if (!shared_vertices_problem(state).empty()) r.shared_vertices = false;
      }
    ImGui::EndCombo();
  }
  const std::string shared_problem = shared_vertices_problem(state);
  bool shared = r.shared_vertices;
  ImGui::BeginDisabled(!shared_problem.empty());
  if (ImGui::Checkbox("shared vertices (tetlets)", &shared)) r.shared_vertices = shared;
  ImGui::EndDisabled();
  if (!shared_problem.empty() && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("%s", shared_problem.c_str());

  const bool color = r.quantity == volume::Quantity::Color;
  const bool march = r.march.enabled;
  if (color && !march) {
    // Larger tables take seconds to build on the CPU (exact integrals per texel): the CLI has them.
    static constexpr std::array<int, 4> kTables = {0, 16, 32, 64};
    const std::string label = r.preintegration_size ? std::to_string(r.preintegration_size) + "^3" : "off (exact)";
    if (ImGui::BeginCombo("pre-integration", label.c_str())) {
      for (int n : kTables)
        if (ImGui::Selectable(n ? (std::to_string(n) + "^3").c_str() : "off (exact)", uint32_t(n) == r.preintegration_size))
          r.preintegration_size = uint32_t(n);
      ImGui::EndCombo();
    }
  }
  if (march) {
    const Bounds& b = state.dataset().bounds;
    const double diagonal = glm::length(b.max - b.min);
    float step = float(r.march.step / diagonal * 100.0);
    if (ImGui::SliderFloat("march step (% of diagonal)", &step, 0.05f, 10.0f, "%.2f", ImGuiSliderFlags_Logarithmic))
      r.march.step = double(step) / 100.0 * diagonal;
    if (r.quantity == volume::Quantity::Isosurface) {
      float iso = float(r.march.isovalue);
      if (ImGui::SliderFloat("isovalue", &iso, float(state.dataset().scalar_lo), float(state.dataset().scalar_hi))) r.march.isovalue = double(iso);
    }
  }
  if (color || march) {
    double& scale = color ? r.transfer.density_scale : r.march.density_scale;
    float value = float(scale);
    if (ImGui::SliderFloat("density scale", &value, 0.01f, 100.0f, "%.3g", ImGuiSliderFlags_Logarithmic)) scale = double(value);
  } else {
    ImGui::TextDisabled("density scale: applied at load (--density-scale)");
  }
}

void draw_frame_plan(const ViewState&, const FrameStats& stats) { draw_frame_plan_rows(stats); }

}  // namespace prismoid::app
