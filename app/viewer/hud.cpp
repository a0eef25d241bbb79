// The HUD: what the last frame cost and what it drew, in the top-right corner.
#include <imgui.h>

#include <cmath>

#include "app/common/volume_options.hpp"
#include "app/viewer/panels.hpp"

namespace prismoid::app {

void draw_hud(const FrameStats& stats, const ViewState& state) {
  const ImGuiViewport* viewport = ImGui::GetMainViewport();
  ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x + viewport->WorkSize.x - 10.0f, viewport->WorkPos.y + 10.0f), ImGuiCond_Always,
                          ImVec2(1.0f, 0.0f));
  ImGui::SetNextWindowBgAlpha(0.6f);
  const ImGuiWindowFlags flags = ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                                 ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoMove;
  if (!ImGui::Begin("HUD", nullptr, flags)) {
    ImGui::End();
    return;
  }
  ImGui::Text("%s", stats.frame.device.c_str());
  ImGui::Text("%s, %s", state.mode.c_str(), quantity_name(state.settings.resolve.quantity));
  ImGui::Text("frame (CPU) %.2f ms", stats.cpu_frame_ms);
  if (stats.resolution_level > 3)
    ImGui::Text("moving: a coarse proxy of the data (%llu cells) at 1/8 resolution (holding %.0f ms a frame)",
                static_cast<unsigned long long>(stats.cells), stats.target_ms);
  else if (stats.resolution_level > 0)
    ImGui::Text("moving: 1/%u resolution (holding %.0f ms a frame)", 1u << stats.resolution_level, stats.target_ms);
  else
    ImGui::Text("full resolution");
  double gpu_total = 0.0;
  for (const auto& p : stats.frame.passes) {
    if (std::isfinite(p.gpu_ms)) gpu_total += p.gpu_ms;
    ImGui::Text("  %s %.3f ms", p.name.c_str(), p.gpu_ms);
  }
  ImGui::Text("GPU total %.3f ms", gpu_total);
  ImGui::Text("cells drawn %llu", static_cast<unsigned long long>(stats.cells));
  const frame::FrameReport& report = stats.report();
  if (report.counted) ImGui::Text("fragments shaded %llu", static_cast<unsigned long long>(report.fragments));
  ImGui::Text("mesh on GPU %.1f MiB", double(report.mesh_bytes) / (1024.0 * 1024.0));
  ImGui::End();
}

}  // namespace prismoid::app
