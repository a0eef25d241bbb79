#pragma once
// The compare section of the side panel (off, split with B's mode and quantity, difference)
// and what the view shows about the comparison: each half's label, B's passes and the
// difference statistics with the heat map's legend, appended to the HUD.
#include "app/viewer/compare_view.hpp"
#include "app/viewer/panels.hpp"
#include "app/viewer/view_state.hpp"

namespace prismoid::app {

void draw_compare_section(ViewState& state, PanelState& panel);
void draw_compare_overlay(const CompareStatus& status, const ViewState& state, const FrameStats& stats);

}  // namespace prismoid::app
